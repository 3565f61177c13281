// Materials that would render negative or made-up radiance are errors
// naming the file, the line and the value (issue 49 item 4), and so are GGX
// roughnesses outside (0, 1] (MTL `Pr`, AFF `fg`); legal but extreme values
// still load.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "nodetrace/tracer/scene/scene_loader.hpp"
#include "test_scene_support.hpp"
#include "test_support.hpp"

namespace {

using nodetrace::testing::TempDir;
using nodetrace::testing::write_file;
using nodetrace::tracer::open_scene;
using nodetrace::tracer::testing::scene_error_of;

constexpr const char* kTriangle = "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl a\nf 1 2 3\n";

struct BadMaterial {
  const char* text;
  const char* expected;  // file:line, then the value
  const char* value;
};

// Opening `scene` fails with a message holding bad.expected and bad.value.
void expect_refused(const std::filesystem::path& scene, const BadMaterial& bad) {
  const std::string message = scene_error_of([&] { open_scene(scene.string()); });
  EXPECT_NE(message.find(bad.expected), std::string::npos) << bad.text << "\n-> " << message;
  EXPECT_NE(message.find(bad.value), std::string::npos) << bad.text << "\n-> " << message;
}

// An OBJ file of one triangle whose MTL file is bad.text, refused.
void expect_mtl_refused(const BadMaterial& bad) {
  TempDir dir;
  write_file(dir / "m.mtl", bad.text);
  write_file(dir / "s.obj", kTriangle);
  expect_refused(dir / "s.obj", bad);
}

// An AFF file bad.text, refused.
void expect_aff_refused(const BadMaterial& bad) {
  TempDir dir;
  write_file(dir / "bad.aff", bad.text);
  expect_refused(dir / "bad.aff", bad);
}

TEST(BadMaterials, MtlNegativeNanOrZeroIorNameFileLineAndValue) {
  const BadMaterial cases[] = {
      {"newmtl a\nKd 0.5 -0.25 0.5\n", "m.mtl:2:", "-0.25"},
      {"newmtl a\n\nKs nan 0 0\n", "m.mtl:3:", "nan"},
      {"newmtl a\nKa 0 0 0\nNi 0\n", "m.mtl:3:", "Ni 0"},
      {"newmtl a\nNi -1.5\n", "m.mtl:2:", "-1.5"},
      {"newmtl a\nKe 1 1 1e39\n", "m.mtl:2:", "1e39"},
      {"newmtl a\nd -0.5\n", "m.mtl:2:", "-0.5"},
  };
  for (const auto& bad : cases) expect_mtl_refused(bad);
}

TEST(BadMaterials, AffNegativeColourOrIorNamesFileLineAndValue) {
  const BadMaterial cases[] = {
      {"f 1 -0.5 1 0.5 0 1 0 1\np 3 0 0 0 1 0 0 0 1 0\n", "bad.aff:1:", "'-0.5'"},
      {"f 1 1 1 0.5 0 1 0 -1.5\np 3 0 0 0 1 0 0 0 1 0\n", "bad.aff:1:", "'-1.5'"},
      {"fm 0 0 0\n0.1 0.1 -2\n0 0 0 1 0 1\np 3 0 0 0 1 0 0 0 1 0\n", "bad.aff:2:", "'-2'"},
      {"f 1 1 1 0.5 0 1 0 nan\np 3 0 0 0 1 0 0 0 1 0\n", "bad.aff:1:", "'nan'"},
      {"am -0.1 0 0\np 3 0 0 0 1 0 0 0 1 0\n", "bad.aff:1:", "'-0.1'"},
  };
  for (const auto& bad : cases) expect_aff_refused(bad);
}

TEST(BadMaterials, MtlRoughnessNotAboveZeroAndAtMostOneNamesFileLineAndValue) {
  const BadMaterial cases[] = {
      {"newmtl a\nKs 1 1 1\nPr 0\n", "m.mtl:3:", "Pr 0"},  // a smooth mirror is illum 3
      {"newmtl a\nPr 1.5\n", "m.mtl:2:", "1.5"},
      {"newmtl a\nPr nan\n", "m.mtl:2:", "nan"},
      {"newmtl a\nPr -0.25\n", "m.mtl:2:", "-0.25"},
  };
  for (const auto& bad : cases) expect_mtl_refused(bad);
}

TEST(BadMaterials, AffGgxLobeOfBadColourOrRoughnessNamesFileLineAndValue) {
  const BadMaterial cases[] = {
      {"f 1 1 1 0.5 0 1 0 1\nfg 1 1 1 0\np 3 0 0 0 1 0 0 0 1 0\n", "bad.aff:2:", "got 0"},
      {"f 1 1 1 0.5 0 1 0 1\n\nfg 1 1 1 1.5\np 3 0 0 0 1 0 0 0 1 0\n", "bad.aff:3:", "got 1.5"},
      {"f 1 1 1 0.5 0 1 0 1\nfg 1 1 1 nan\np 3 0 0 0 1 0 0 0 1 0\n", "bad.aff:2:", "'nan'"},
      {"f 1 1 1 0.5 0 1 0 1\nfg 1 -0.5 1 0.5\np 3 0 0 0 1 0 0 0 1 0\n", "bad.aff:2:", "'-0.5'"},
      {"fg 1 1 1 0.5\np 3 0 0 0 1 0 0 0 1 0\n", "bad.aff:1:", "'fg' needs a material"},
  };
  for (const auto& bad : cases) expect_aff_refused(bad);
}

TEST(BadMaterials, ExtremeLegalValuesStillLoad) {
  TempDir dir;
  write_file(dir / "m.mtl", "newmtl a\nKd 3e38 0 3.4e38\nNs 1e30\nNi 1e-30\n");
  write_file(dir / "s.obj", kTriangle);
  const auto obj = open_scene((dir / "s.obj").string())->at_time(0);
  EXPECT_FLOAT_EQ(obj.materials[0].diffuse.z, 3.4e38f);
  EXPECT_FLOAT_EQ(obj.materials[0].shininess, 1e30f);
  // BART's files write an index of refraction of 0 (read as 1).
  write_file(dir / "ok.aff", "f 3e38 1 1 1 0 1e30 0.5 0\np 3 0 0 0 1 0 0 0 1 0\n");
  const auto aff = open_scene((dir / "ok.aff").string())->at_time(0);
  EXPECT_FLOAT_EQ(aff.materials.back().diffuse.x, 3e38f);
  EXPECT_FLOAT_EQ(aff.materials.back().ior, 1.0f);
}

}  // namespace
