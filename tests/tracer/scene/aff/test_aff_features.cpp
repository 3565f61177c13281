// AFF features on small files written to a temporary directory: every
// keyword, transforms, Kochanek-Bartels keyframes, includes and bad input.
#include <gtest/gtest.h>

#include <cmath>

#include "nodetrace/tracer/scene/scene_loader.hpp"
#include "test_scene_support.hpp"
#include "test_support.hpp"

namespace {

using nodetrace::testing::TempDir;
using nodetrace::testing::write_file;
using nodetrace::tracer::open_scene;
using nodetrace::tracer::Scene;
using nodetrace::tracer::SceneError;
using nodetrace::tracer::Vec3;
using nodetrace::tracer::testing::expect_near;
using nodetrace::tracer::testing::scene_error_of;

Scene load_text(const TempDir& dir, const std::string& text, double time = 0) {
  write_file(dir / "scene.aff", text);
  return open_scene((dir / "scene.aff").string())->at_time(time);
}

constexpr const char* kEveryKeyword = R"(# a comment line
% another comment style
v
from 0 0 10
at 0 0 0
up 0 1 0
angle 30
hither 0.1
resolution 320 240
b 0.1 0.2 0.3
am 0.5 0.5 0.5   # trailing comment
l 1 2 3
l 4 5 6 0.5 0.25 0.125
f 1 0.5 0 0.8 0.2 10 0 1
p 4
0 0 0
1 0 0
1 1 0
0 1 0
fm 0.1 0.1 0.1  0.2 0.3 0.4  0.5 0.5 0.5  20 0.7 1.5
pp 3
0 0 1  0 0 1
1 0 1  0 0 1
0 1 1  0 0 1
tpp 3
0 0 2  0 0 1  0 0
1 0 2  0 0 1  1 0
0 1 2  0 0 1  0 1
s 5 5 5 1
c 0 0 0 1  0 2 0 0.5
m
 vertices 4
  0 0 3
  1 0 3
  1 1 3
  0 1 3
 normals 4
  0 0 1
  0 0 1
  0 0 1
  0 0 1
 texturecoords 4 this_texture_does_not_exist.ppm
  0 0
  1 0
  1 1
  0 1
 triangles 2
  0 1 2  0 1 2  0 1 2
  0 2 3  0 2 3  0 2 3
)";

TEST(AffFeatures, EveryKeywordIsParsed) {
  TempDir dir;
  const Scene scene = load_text(dir, kEveryKeyword);
  // p (quad: 2) + pp (1) + tpp (1) + sphere (320) + open cone (48) + mesh (2).
  EXPECT_EQ(scene.triangles.size(), 2u + 1 + 1 + 320 + 48 + 2);
  EXPECT_EQ(scene.name, "scene.aff");
  ASSERT_TRUE(scene.camera.has_value());
  expect_near(scene.camera->eye, {0, 0, 10});
  expect_near(scene.camera->look_at, {0, 0, 0});
  expect_near(scene.camera->up, {0, 1, 0});
  EXPECT_FLOAT_EQ(scene.camera->fov_y_degrees, 30);
  EXPECT_EQ(scene.suggested_width, 320);
  EXPECT_EQ(scene.suggested_height, 240);
  expect_near(scene.background, {0.1f, 0.2f, 0.3f});
  expect_near(scene.ambient, {0.5f, 0.5f, 0.5f});
  ASSERT_EQ(scene.lights.size(), 2u);
  expect_near(scene.lights[0].position, {1, 2, 3});
  expect_near(scene.lights[0].color, {1, 1, 1});
  expect_near(scene.lights[1].color, {0.5f, 0.25f, 0.125f});

  ASSERT_EQ(scene.materials.size(), 2u);
  const auto& nff = scene.materials[0];
  expect_near(nff.diffuse, {0.8f, 0.4f, 0});  // colour * Kd
  EXPECT_FLOAT_EQ(nff.reflectance, 0.2f);      // Ks
  EXPECT_FLOAT_EQ(nff.shininess, 10);
  EXPECT_FLOAT_EQ(nff.transmittance, 0);
  const auto& extended = scene.materials[1];
  ASSERT_TRUE(extended.ambient.has_value());
  expect_near(*extended.ambient, {0.1f, 0.1f, 0.1f});
  expect_near(extended.diffuse, {0.2f, 0.3f, 0.4f});
  expect_near(extended.specular, {0.5f, 0.5f, 0.5f});
  EXPECT_FLOAT_EQ(extended.reflectance, 0.5f);
  EXPECT_FLOAT_EQ(extended.shininess, 20);
  EXPECT_FLOAT_EQ(extended.transmittance, 0.7f);
  EXPECT_FLOAT_EQ(extended.ior, 1.5f);
  EXPECT_EQ(scene.triangles.front().material, 0u);
  EXPECT_EQ(scene.triangles.back().material, 1u);

  // The polygon is fanned from its first vertex.
  expect_near(scene.triangles[0].v0, {0, 0, 0});
  expect_near(scene.triangles[0].v1, {1, 0, 0});
  expect_near(scene.triangles[0].v2, {1, 1, 0});
  expect_near(scene.triangles[1].v2, {0, 1, 0});
  // Vertex normals are kept (the patches and the mesh have them).
  ASSERT_EQ(scene.vertex_normals.size(), 3 * scene.triangles.size());
  expect_near(scene.vertex_normals[6], {0, 0, 1});
  // Sphere vertices lie on the sphere.
  for (std::size_t i = 4; i < 4 + 320; ++i) {
    EXPECT_NEAR(length(scene.triangles[i].v0 - Vec3{5, 5, 5}), 1.0f, 1e-5f);
  }
  // The mesh's last triangle, through its indices.
  expect_near(scene.triangles.back().v1, {1, 1, 3});
  EXPECT_EQ(open_scene((dir / "scene.aff").string())->animation().frames, 1u);
}

TEST(AffFeatures, StaticTransformsScaleRotateThenTranslateAndNest) {
  TempDir dir;
  const Scene scene = load_text(dir, R"(
xs 2 2 2  0 0 1 90  10 0 0
{
  p 3
  1 0 0
  0 1 0
  0 0 1
  xs 1 1 1  1 0 0 0  0 0 5
  {
    p 3
    1 0 0
    0 1 0
    0 0 1
  }
}
p 3
1 0 0
0 1 0
0 0 1
)");
  ASSERT_EQ(scene.triangles.size(), 3u);
  expect_near(scene.triangles[0].v0, {10, 2, 0});   // (1,0,0) -> scaled (2,0,0) -> rotated (0,2,0)
  expect_near(scene.triangles[0].v1, {8, 0, 0});
  expect_near(scene.triangles[0].v2, {10, 0, 2});
  expect_near(scene.triangles[1].v0, {10, 2, 10});  // inner translation is scaled and rotated too
  expect_near(scene.triangles[2].v0, {1, 0, 0});    // after '}' the transform no longer applies
}

constexpr const char* kAnimated = R"(
a 0 4 5
x slide { p 3  0 0 0  0 0 0.1  0.1 0 0 }
x spin { p 3  1 0 0  1 0 0.1  1.1 0 0 }
x grow { p 3  1 1 1  1 1 1.1  1.1 1 1 }
l lamp 0 0 0 1 1 1
k slide {
  transl 3
  0  0 0 0  0 0 0
  2  5 1 0  0.5 0.2 -0.3
  4  5 6 2  0 0 0
}
k spin {
  rot 3
  0  0 1 0 0    0 0 0
  2  0 1 0 90   0.3 0 0
  4  0 1 0 180  0 0 0
}
k grow {
  scale 2
  0  1 1 1  0 0 0
  4  3 3 3  0 0 0
}
k lamp {
  transl 2
  0  1 2 3  0 0 0
  4  4 5 6  0 0 0
}
k camera {
  transl 2
  0  1 2 3  0 0 0
  4  1 2 7  0 0 0
  rot 1
  0  0 1 0 90  0 0 0
}
)";

TEST(AffFeatures, KeyframedTransformsHitTheirKeysExactly) {
  TempDir dir;
  write_file(dir / "anim.aff", kAnimated);
  const auto source = open_scene((dir / "anim.aff").string());
  EXPECT_EQ(source->animation().frames, 5u);
  EXPECT_DOUBLE_EQ(source->animation().start, 0);
  EXPECT_DOUBLE_EQ(source->animation().end, 4);
  EXPECT_DOUBLE_EQ(source->animation().time_of_frame(2), 2);

  const Scene at0 = source->at_frame(0), at2 = source->at_frame(2), at4 = source->at_frame(4);
  expect_near(at0.triangles[0].v0, {0, 0, 0});
  expect_near(at2.triangles[0].v0, {5, 1, 0});
  expect_near(at4.triangles[0].v0, {5, 6, 2});
  // Rotation about y by 0, 90 and 180 degrees.
  expect_near(at0.triangles[1].v0, {1, 0, 0});
  expect_near(at2.triangles[1].v0, {0, 0, -1});
  expect_near(at4.triangles[1].v0, {-1, 0, 0});
  // Scale keys.
  expect_near(at0.triangles[2].v0, {1, 1, 1});
  expect_near(at4.triangles[2].v0, {3, 3, 3});
  // Lights follow their keyframes.
  expect_near(at0.lights[0].position, {1, 2, 3});
  expect_near(at4.lights[0].position, {4, 5, 6});
  // The camera: eye on its path, `rot` turning the -z view direction.
  ASSERT_TRUE(at4.camera.has_value());
  expect_near(at4.camera->eye, {1, 2, 7});
  expect_near(at4.camera->look_at, {0, 2, 7});

  // Between keys the spline moves smoothly, not outside the key hull here.
  const Scene at1 = source->at_time(1);
  EXPECT_GT(at1.triangles[0].v0.x, 0.5f);
  EXPECT_LT(at1.triangles[0].v0.x, 5.5f);
  expect_near(source->at_time(3).triangles[2].v0, {2.5f, 2.5f, 2.5f}, 0.3f);
  // Before the first and after the last key the ends hold.
  expect_near(source->at_time(-1).triangles[0].v0, {0, 0, 0});
  expect_near(source->at_time(9).triangles[0].v0, {5, 6, 2});
}

TEST(AffFeatures, SplineBetweenKeysFollowsKochanekBartels) {
  // Keys 0, 1, 3 at times 0, 1, 2. With tension, continuity and bias 0 the
  // tangents are Catmull-Rom's (end keys reuse their one difference): at
  // t = 0.5 the Hermite blend gives 0.125 * 1 + 0.5 * 1 - 0.125 * 1.5.
  TempDir dir;
  const Scene smooth = load_text(dir, R"(
x path { p 3  0 0 0  0 0 0.1  0.1 0 0 }
k path { transl 3  0 0 0 0 0 0 0  1 1 0 0 0 0 0  2 3 0 0 0 0 0 }
)", 0.5);
  EXPECT_NEAR(smooth.triangles[0].v0.x, 0.4375f, 1e-5f);
  // Tension 1 flattens every tangent: the blend is the smoothstep h01 = 0.5.
  const Scene tense = load_text(dir, R"(
x path { p 3  0 0 0  0 0 0.1  0.1 0 0 }
k path { transl 3  0 0 0 0 1 0 0  1 1 0 0 1 0 0  2 3 0 0 1 0 0 }
)", 0.5);
  EXPECT_NEAR(tense.triangles[0].v0.x, 0.5f, 1e-5f);
  // Bias 1 at the second key takes its incoming tangent from the previous
  // difference only: 0.125 * 1 + 0.5 * 1 - 0.125 * 1 = 0.5.
  const Scene biased = load_text(dir, R"(
x path { p 3  0 0 0  0 0 0.1  0.1 0 0 }
k path { transl 3  0 0 0 0 0 0 0  1 1 0 0 0 0 1  2 3 0 0 0 0 0 }
)", 0.5);
  EXPECT_NEAR(biased.triangles[0].v0.x, 0.5f, 1e-5f);
}

TEST(AffFeatures, IncludesAreRelativeToTheIncludingFileAndHashed) {
  TempDir dir;
  std::filesystem::create_directories(dir / "parts" / "leaves");
  write_file(dir / "main.aff", "i 0 parts/part.aff\np 3 0 0 0 1 0 0 0 1 0\n");
  write_file(dir / "parts" / "part.aff", "xs 1 1 1 0 0 1 0 0 0 7 { i 0 leaves/leaf.aff }\n");
  write_file(dir / "parts" / "leaves" / "leaf.aff", "p 3 0 0 0 1 0 0 0 1 0\n");
  const auto source = open_scene((dir / "main.aff").string());
  const Scene scene = source->at_time(0);
  ASSERT_EQ(scene.triangles.size(), 2u);
  expect_near(scene.triangles[0].v0, {0, 0, 7});
  expect_near(scene.triangles[1].v0, {0, 0, 0});
  const std::string hash = source->content_hash();
  EXPECT_EQ(open_scene((dir / "main.aff").string())->content_hash(), hash);
  write_file(dir / "parts" / "leaves" / "leaf.aff", "p 3 0 0 0 1 0 0 0 1 1\n");
  EXPECT_NE(open_scene((dir / "main.aff").string())->content_hash(), hash);
}

struct BadInput {
  const char* text;
  const char* expected_location;
  const char* expected_words;
};

// `fe R G B` makes the current material emit until the next `f` or `fm`
// (issue 49 item 1); before any material, or negative, it is an error.
TEST(AffFeatures, FeMakesTheCurrentMaterialEmit) {
  TempDir dir;
  write_file(dir / "lamp.aff", "f 1 1 1 0.5 0 1 0 1\nfe 2 3 4\np 3 0 0 0 1 0 0 0 1 0\n"
                               "f 1 1 1 0.5 0 1 0 1\np 3 0 0 1 1 0 1 0 1 1\n");
  const Scene scene = open_scene((dir / "lamp.aff").string())->at_time(0);
  ASSERT_EQ(scene.triangles.size(), 2u);
  expect_near(scene.materials[scene.triangles[0].material].emission, Vec3{2, 3, 4});
  expect_near(scene.materials[scene.triangles[1].material].emission, Vec3{0, 0, 0});
  write_file(dir / "first.aff", "\nfe 1 1 1\np 3 0 0 0 1 0 0 0 1 0\n");
  const std::string first = scene_error_of([&] { open_scene((dir / "first.aff").string()); });
  EXPECT_NE(first.find("first.aff:2: 'fe' needs a material before it"), std::string::npos) << first;
  write_file(dir / "negative.aff", "f 1 1 1 0.5 0 1 0 1\nfe 1 -1 1\np 3 0 0 0 1 0 0 0 1 0\n");
  const std::string negative = scene_error_of([&] { open_scene((dir / "negative.aff").string()); });
  EXPECT_NE(negative.find("negative.aff:2:"), std::string::npos) << negative;
}

TEST(AffFeatures, BadInputNamesFileLineAndExpectation) {
  const BadInput cases[] = {
      {"p 3\n0 0 0\n1 0 0\n0 1 x1\n", "bad.aff:4:", "number"},
      {"p 3\n0 0 0\n1 nan 0\n0 1 0\n", "bad.aff:3:", "finite"},
      {"b 0 0 0\n\nzz 1 2 3\n", "bad.aff:3:", "unknown keyword 'zz'"},
      {"\ni 0 no_such_file.aff\n", "bad.aff:2:", "no_such_file.aff"},
      {"xs 1 1 1 0 0 1 0 0 0 0\n{\np 3 0 0 0 1 0 0 0 1 0\n", "bad.aff:", "expected '}'"},
      {"}\n", "bad.aff:1:", "'}'"},
      {"m\nvertices 3\n0 0 0 1 0 0 0 1 0\ntriangles 1\n0 1 3\n", "bad.aff:5:", "vertex index below 3"},
      {"p 3 0 0 0 1 0 0", "bad.aff:1:", "end of the file"},
  };
  for (const auto& bad : cases) {
    TempDir dir;
    write_file(dir / "bad.aff", bad.text);
    const std::string message = scene_error_of([&] { open_scene((dir / "bad.aff").string()); });
    EXPECT_NE(message.find(bad.expected_location), std::string::npos) << bad.text << "\n-> " << message;
    EXPECT_NE(message.find(bad.expected_words), std::string::npos) << bad.text << "\n-> " << message;
  }
}

}  // namespace
