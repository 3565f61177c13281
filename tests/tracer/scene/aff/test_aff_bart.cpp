// The paper's BART scenes (../shared/scenes/bart) load with stable figures.
#include <gtest/gtest.h>

#include "nodetrace/tracer/scene/scene_loader.hpp"
#include "test_scene_support.hpp"
#include "test_support.hpp"

namespace {

using nodetrace::tracer::open_scene;
using nodetrace::tracer::Scene;
using nodetrace::tracer::testing::expect_near;

TEST(AffBart, KitchenFrameZero) {
  NODETRACE_SHARED_OR_SKIP(shared);
  const auto source = open_scene((shared / "scenes/bart/kitchen/kitchen.aff").string());
  EXPECT_EQ(source->name(), "kitchen.aff");
  EXPECT_EQ(source->animation().frames, 800u);
  EXPECT_DOUBLE_EQ(source->animation().start, 0);
  EXPECT_DOUBLE_EQ(source->animation().end, 20);
  const Scene scene = source->at_frame(0);
  // 110,561 triangles in the files, 41 of them zero-area (dropped, one warning).
  EXPECT_EQ(scene.triangles.size(), 110520u);
  EXPECT_EQ(scene.vertex_normals.size(), 3u * 110520u);
  ASSERT_EQ(source->warnings().size(), 1u);
  EXPECT_EQ(source->warnings()[0].rfind("41 zero-area triangles dropped (the first at ", 0), 0u);
  EXPECT_EQ(scene.lights.size(), 6u);
  EXPECT_EQ(scene.materials.size(), 27u);
  EXPECT_EQ(scene.suggested_width, 800);
  EXPECT_EQ(scene.suggested_height, 600);
  ASSERT_TRUE(scene.camera.has_value());
  // The `k camera` path overrides the static view.
  expect_near(scene.camera->eye, {3.75f, 2.3f, 3.6f});
  expect_near(scene.camera->look_at, {3.43654f, 1.88019f, 2.74824f});
  EXPECT_FLOAT_EQ(scene.camera->fov_y_degrees, 40);
  expect_near(scene.background, {0.5f, 0.5f, 1.0f});
  expect_near(scene.ambient, {2.5f, 2.5f, 2.5f});
}

TEST(AffBart, KitchenToyCarMovesBetweenFrames) {
  NODETRACE_SHARED_OR_SKIP(shared);
  const auto source = open_scene((shared / "scenes/bart/kitchen/kitchen.aff").string());
  const Scene first = source->at_frame(0), later = source->at_frame(400);
  ASSERT_EQ(first.triangles.size(), later.triangles.size());
  std::size_t moved = 0;
  for (std::size_t i = 0; i < first.triangles.size(); ++i) {
    if (!(first.triangles[i].v0 == later.triangles[i].v0)) ++moved;
  }
  EXPECT_GT(moved, 1000u);                          // the car and its wheels
  EXPECT_LT(moved, first.triangles.size() / 2);     // the kitchen stays put
  EXPECT_FALSE(first.camera->eye == later.camera->eye);
}

TEST(AffBart, RobotsFrameZero) {
  NODETRACE_SHARED_OR_SKIP(shared);
  const auto source = open_scene((shared / "scenes/bart/robots/Robot.aff").string());
  EXPECT_EQ(source->animation().frames, 800u);
  EXPECT_DOUBLE_EQ(source->animation().end, 50);
  const Scene scene = source->at_frame(0);
  // 71,708 triangles in the files, 128 of them zero-area (dropped, one warning).
  EXPECT_EQ(scene.triangles.size(), 71580u);
  ASSERT_EQ(source->warnings().size(), 1u);
  EXPECT_EQ(source->warnings()[0].rfind("128 zero-area triangles dropped (the first at ", 0), 0u);
  EXPECT_EQ(scene.lights.size(), 1u);
  EXPECT_EQ(scene.materials.size(), 62u);
  ASSERT_TRUE(scene.camera.has_value());
  expect_near(scene.camera->eye, {-3.5f, 2, -203});
  EXPECT_NEAR(scene.camera->fov_y_degrees, 36.86989f, 1e-4);

  // Robots walk: frame 200 differs from frame 0.
  const Scene later = source->at_frame(200);
  std::size_t moved = 0;
  for (std::size_t i = 0; i < scene.triangles.size(); ++i) {
    if (!(scene.triangles[i].v1 == later.triangles[i].v1)) ++moved;
  }
  EXPECT_GT(moved, 1000u);
}

}  // namespace
