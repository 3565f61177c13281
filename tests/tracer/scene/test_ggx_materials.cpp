// How a scene asks for a GGX lobe: MTL `Pr` (roughness) with `Ks` as the
// lobe's colour, which then feeds nothing else; AFF `fg R G B roughness`
// after a material, kept through its `fe`, gone at the next material.
#include <gtest/gtest.h>

#include "nodetrace/tracer/scene/scene_loader.hpp"
#include "test_scene_support.hpp"
#include "test_support.hpp"

namespace nodetrace::tracer {
namespace {

using nodetrace::testing::TempDir;
using nodetrace::testing::write_file;
using testing::expect_near;

TEST(GgxMaterials, MtlPrMakesKsTheColourOfAGgxLobeAndOfNothingElse) {
  TempDir dir;
  write_file(dir / "m.mtl",
             "newmtl shiny\nKd 0.2 0.3 0.4\nKs 0.6 0.5 0.4\nNs 80\nPr 0.3\nillum 3\n"
             "newmtl phong\nKd 0.2 0.3 0.4\nKs 0.6 0.5 0.4\nNs 80\nillum 3\n");
  write_file(dir / "s.obj",
             "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl shiny\nf 1 2 3\nusemtl phong\nf 1 3 2\n");
  const Scene scene = open_scene((dir / "s.obj").string())->at_time(0);
  const Material& shiny = scene.materials[scene.triangles[0].material];
  expect_near(shiny.ggx_color, {0.6f, 0.5f, 0.4f});
  EXPECT_FLOAT_EQ(shiny.ggx_roughness, 0.3f);
  expect_near(shiny.diffuse, {0.2f, 0.3f, 0.4f});
  // Ks is the lobe's: no Phong highlight, no mirror from illum 3.
  expect_near(shiny.specular, {0, 0, 0});
  EXPECT_EQ(shiny.shininess, 0);
  EXPECT_EQ(shiny.reflectance, 0);
  // Without Pr, as before: Ks the Phong colour and the mirror's weight.
  const Material& phong = scene.materials[scene.triangles[1].material];
  EXPECT_EQ(phong.ggx_roughness, 0);
  expect_near(phong.specular, {0.6f, 0.5f, 0.4f});
  EXPECT_FLOAT_EQ(phong.reflectance, 0.5f);
}

TEST(GgxMaterials, AffFgGivesTheCurrentMaterialAGgxLobeUntilTheNextMaterial) {
  TempDir dir;
  write_file(dir / "s.aff",
             "fm 0 0 0 0.5 0.5 0.5 0.2 0.2 0.2 10 0 1\nfg 0.9 0.8 0.7 0.25\np 3 0 0 0 1 0 0 0 1 0\n"
             "fe 2 2 2\np 3 0 0 1 1 0 1 0 1 1\n"
             "fm 0 0 0 0.5 0.5 0.5 0.2 0.2 0.2 10 0 1\np 3 0 0 2 1 0 2 0 1 2\n");
  const Scene scene = open_scene((dir / "s.aff").string())->at_time(0);
  const Material& glossy = scene.materials[scene.triangles[0].material];
  expect_near(glossy.ggx_color, {0.9f, 0.8f, 0.7f});
  EXPECT_FLOAT_EQ(glossy.ggx_roughness, 0.25f);
  // The material's other lobes stay.
  expect_near(glossy.diffuse, {0.5f, 0.5f, 0.5f});
  EXPECT_FLOAT_EQ(glossy.shininess, 10);
  const Material& emitting = scene.materials[scene.triangles[1].material];
  EXPECT_FLOAT_EQ(emitting.ggx_roughness, 0.25f);
  expect_near(emitting.emission, {2, 2, 2});
  EXPECT_EQ(scene.materials[scene.triangles[2].material].ggx_roughness, 0);
}

}  // namespace
}  // namespace nodetrace::tracer
