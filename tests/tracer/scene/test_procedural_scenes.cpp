// Built-in procedural scenes: counts, determinism, materials, and the
// closed sphere helper.
#include <gtest/gtest.h>

#include <map>
#include <tuple>

#include "nodetrace/tracer/scene/scene_geometry.hpp"
#include "nodetrace/tracer/scene/scene_loader.hpp"
#include "test_scene_support.hpp"

namespace {

using nodetrace::tracer::builtin_scenes;
using nodetrace::tracer::default_scene_name;
using nodetrace::tracer::make_sphere_mesh;
using nodetrace::tracer::open_scene;
using nodetrace::tracer::Scene;
using nodetrace::tracer::SceneLoadOptions;
using nodetrace::tracer::Vec3;
using nodetrace::tracer::testing::scene_error_of;
using nodetrace::tracer::testing::vertex_data_hash;

TEST(ProceduralScenes, ListingOrderDefaultsAndCounts) {
  const auto scenes = builtin_scenes();
  ASSERT_EQ(scenes.size(), 3u);
  EXPECT_EQ(scenes[0].name, "sphereflake");
  EXPECT_EQ(scenes[1].name, "mountain");
  EXPECT_EQ(scenes[2].name, "forest");
  EXPECT_EQ(default_scene_name(), "sphereflake");
  EXPECT_EQ(scenes[0].triangles, 100882u);
  EXPECT_EQ(scenes[1].triangles, 34050u);
  EXPECT_EQ(scenes[2].triangles, 98720u);
  for (const auto& info : scenes) {
    EXPECT_FALSE(info.description.empty());
    EXPECT_LT(info.min_triangles, info.triangles);
    EXPECT_GT(info.max_triangles, info.triangles);
    EXPECT_EQ(open_scene(info.name)->at_time(0).triangles.size(), info.triangles) << info.name;
  }
}

TEST(ProceduralScenes, SizesSpanFiveToTwoHundredFiftyThousandTriangles) {
  const std::map<std::string, std::uint64_t> expected = {
      {"sphereflake:1", 16642},  {"sphereflake:2", 42562}, {"sphereflake:4", 232102},
      {"mountain:6", 9474},      {"mountain:8", 132354},   {"forest:1", 13248},
      {"forest:2", 45300},       {"forest:5", 269664},
  };
  for (const auto& [spec, triangles] : expected) {
    EXPECT_EQ(open_scene(spec)->at_time(0).triangles.size(), triangles) << spec;
  }
  SceneLoadOptions options;
  options.builtin_size = 6;
  EXPECT_EQ(open_scene("mountain", options)->at_time(0).triangles.size(), 9474u);
}

TEST(ProceduralScenes, VertexDataIsDeterministic) {
  // Literal hashes: a change in any generated triangle (or a platform whose
  // generator output differs) shows here.
  EXPECT_EQ(vertex_data_hash(open_scene("sphereflake")->at_time(0)), 15084789083231000021ULL);
  EXPECT_EQ(vertex_data_hash(open_scene("mountain")->at_time(0)), 10596980345177479602ULL);
  EXPECT_EQ(vertex_data_hash(open_scene("forest")->at_time(0)), 13235640082977383254ULL);
  EXPECT_EQ(vertex_data_hash(open_scene("forest:2")->at_time(0)), vertex_data_hash(open_scene("forest:2")->at_time(5)));
}

TEST(ProceduralScenes, EveryScenesHasMirrorsGlassLightsAndACamera) {
  for (const auto& info : builtin_scenes()) {
    const Scene scene = open_scene(info.name)->at_time(0);
    EXPECT_EQ(scene.name, info.name);
    bool mirror = false, glass = false;
    std::vector<bool> used(scene.materials.size(), false);
    for (const auto& t : scene.triangles) used.at(t.material) = true;
    for (std::size_t m = 0; m < scene.materials.size(); ++m) {
      EXPECT_TRUE(used[m]) << info.name << " material " << scene.materials[m].name << " unused";
      mirror = mirror || (scene.materials[m].reflectance >= 0.5f && scene.materials[m].transmittance == 0);
      glass = glass || (scene.materials[m].transmittance > 0.5f && scene.materials[m].ior > 1.2f);
    }
    EXPECT_TRUE(mirror) << info.name;
    EXPECT_TRUE(glass) << info.name;
    EXPECT_GE(scene.lights.size(), 2u) << info.name;
    // Smooth unit normals, one per corner.
    ASSERT_EQ(scene.vertex_normals.size(), 3 * scene.triangles.size()) << info.name;
    for (std::size_t i = 0; i < scene.vertex_normals.size(); i += 97) {
      EXPECT_NEAR(length(scene.vertex_normals[i]), 1.0f, 1e-4f) << info.name;
    }
    ASSERT_TRUE(scene.camera.has_value()) << info.name;
    // The camera looks at the scene: its target is inside the bounds.
    const auto box = scene.bounds();
    for (int axis = 0; axis < 3; ++axis) {
      EXPECT_GE(scene.camera->look_at[axis], box.lo[axis]) << info.name;
      EXPECT_LE(scene.camera->look_at[axis], box.hi[axis]) << info.name;
    }
  }
}

TEST(ProceduralScenes, HashesNameSizesAndRejectsBadSizes) {
  EXPECT_EQ(open_scene("forest:2")->content_hash(), open_scene("forest:2")->content_hash());
  EXPECT_NE(open_scene("forest:2")->content_hash(), open_scene("forest:3")->content_hash());
  EXPECT_EQ(open_scene("forest")->content_hash(), open_scene("forest:3")->content_hash());
  EXPECT_NE(scene_error_of([] { open_scene("forest:99"); }).find("out of range 1..5"), std::string::npos);
  EXPECT_NE(scene_error_of([] { open_scene("forest:x"); }).find("integer size"), std::string::npos);
}

TEST(SphereMesh, ClosedWatertightAndOnTheSphere) {
  for (int subdivisions = 0; subdivisions <= 3; ++subdivisions) {
    const Vec3 center{1, -2, 3};
    const auto triangles = make_sphere_mesh(center, 2.5f, subdivisions, 7);
    ASSERT_EQ(triangles.size(), 20u << (2 * subdivisions));
    // Every directed edge appears once and its reverse once: closed and
    // consistently wound, with bit-identical shared vertices.
    using Point = std::tuple<float, float, float>;
    std::map<std::pair<Point, Point>, int> edges;
    for (const auto& t : triangles) {
      EXPECT_EQ(t.material, 7u);
      const Point p[3] = {{t.v0.x, t.v0.y, t.v0.z}, {t.v1.x, t.v1.y, t.v1.z}, {t.v2.x, t.v2.y, t.v2.z}};
      for (int i = 0; i < 3; ++i) ++edges[{p[i], p[(i + 1) % 3]}];
      for (const Vec3* v : {&t.v0, &t.v1, &t.v2}) EXPECT_NEAR(length(*v - center), 2.5f, 1e-5f);
      // Outward facing: the normal points away from the centre.
      EXPECT_GT(dot(cross(t.v1 - t.v0, t.v2 - t.v0), t.v0 - center), 0);
    }
    for (const auto& [edge, count] : edges) {
      EXPECT_EQ(count, 1);
      EXPECT_EQ(edges.count({edge.second, edge.first}), 1u);
    }
  }
}

}  // namespace
