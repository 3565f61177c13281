// No invented light without a word (issue 49 item 3): the light a scene
// gets that its file does not give is said in Scene::default_light (and a
// warning for OBJ), and SceneLoadOptions::default_lights = false leaves it out.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "nodetrace/tracer/scene/scene_loader.hpp"
#include "test_support.hpp"

namespace {

using nodetrace::testing::TempDir;
using nodetrace::testing::write_file;
using nodetrace::tracer::open_scene;
using nodetrace::tracer::SceneLoadOptions;

constexpr const char* kObj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
constexpr const char* kAffTriangle = "f 1 1 1 1 0 0 0 1\np 3 0 0 0 1 0 0 0 1 0\n";

TEST(DefaultLight, AnObjWithoutLightGetsKeyAndFillSaidInTheSceneAndAWarning) {
  TempDir dir;
  write_file(dir / "s.obj", kObj);
  const auto source = open_scene((dir / "s.obj").string());
  const auto scene = source->at_time(0);
  EXPECT_EQ(scene.lights.size(), 2u);
  EXPECT_FLOAT_EQ(scene.ambient.x, 0.1f);
  EXPECT_NE(scene.default_light.find("key light"), std::string::npos) << scene.default_light;
  const auto warnings = source->warnings();
  EXPECT_TRUE(std::any_of(warnings.begin(), warnings.end(), [&](const std::string& w) {
    return w.find("s.obj") != std::string::npos && w.find(scene.default_light) != std::string::npos;
  }));
}

TEST(DefaultLight, NoneLeavesAnObjUnlitAndSaysNothing) {
  TempDir dir;
  write_file(dir / "s.obj", kObj);
  const auto source = open_scene((dir / "s.obj").string(), SceneLoadOptions{.default_lights = false});
  const auto scene = source->at_time(0);
  EXPECT_TRUE(scene.lights.empty());
  EXPECT_FLOAT_EQ(scene.ambient.x, 0.0f);
  EXPECT_TRUE(scene.default_light.empty());
  EXPECT_TRUE(source->warnings().empty());
}

TEST(DefaultLight, AnAffWithoutAmGetsAmbientPointOneSaidInTheSceneAndNoneGivesZero) {
  TempDir dir;
  write_file(dir / "no_am.aff", kAffTriangle);
  const auto given = open_scene((dir / "no_am.aff").string())->at_time(0);
  EXPECT_FLOAT_EQ(given.ambient.x, 0.1f);
  EXPECT_NE(given.default_light.find("'am'"), std::string::npos) << given.default_light;
  const auto none = open_scene((dir / "no_am.aff").string(), SceneLoadOptions{.default_lights = false})->at_time(0);
  EXPECT_FLOAT_EQ(none.ambient.x, 0.0f);
  EXPECT_TRUE(none.default_light.empty());
  write_file(dir / "am.aff", std::string("am 0.3 0.3 0.3\n") + kAffTriangle);
  const auto stated = open_scene((dir / "am.aff").string(), SceneLoadOptions{.default_lights = false})->at_time(0);
  EXPECT_FLOAT_EQ(stated.ambient.x, 0.3f);
  EXPECT_TRUE(stated.default_light.empty());
}

}  // namespace
