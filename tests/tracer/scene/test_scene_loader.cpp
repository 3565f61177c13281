// open_scene dispatch and `tracer scenes`.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "nodetrace/tracer/scene/scene_loader.hpp"
#include "test_scene_support.hpp"
#include "test_support.hpp"

namespace {

using nodetrace::testing::program;
using nodetrace::testing::run_command;
using nodetrace::testing::TempDir;
using nodetrace::testing::write_file;
using nodetrace::tracer::open_scene;
using nodetrace::tracer::testing::scene_error_of;

TEST(SceneLoader, UnknownSpecListsTheBuiltins) {
  const std::string message = scene_error_of([] { open_scene("no-such-scene"); });
  EXPECT_NE(message.find("no-such-scene"), std::string::npos) << message;
  EXPECT_NE(message.find("sphereflake, mountain, forest"), std::string::npos) << message;
}

TEST(SceneLoader, UnsupportedFileTypeAndMissingAffAreErrors) {
  TempDir dir;
  write_file(dir / "scene.ply", "ply\n");
  const std::string ply = scene_error_of([&] { open_scene((dir / "scene.ply").string()); });
  EXPECT_NE(ply.find("expected .obj or .aff"), std::string::npos) << ply;
  const std::string aff = scene_error_of([&] { open_scene((dir / "absent.aff").string()); });
  EXPECT_NE(aff.find("absent.aff"), std::string::npos) << aff;
}

TEST(SceneLoader, ExtensionsAreCaseInsensitive) {
  TempDir dir;
  write_file(dir / "UPPER.AFF", "p 3 0 0 0 1 0 0 0 1 0\n");
  EXPECT_EQ(open_scene((dir / "UPPER.AFF").string())->at_time(0).triangles.size(), 1u);
}

TEST(ScenesCommand, ListsBuiltinsAsTextAndJson) {
  const auto text = run_command(program("tracer").string() + " scenes");
  ASSERT_EQ(text.exit_code, 0) << text.err;
  EXPECT_NE(text.out.find("sphereflake"), std::string::npos);
  EXPECT_NE(text.out.find("100882"), std::string::npos);
  EXPECT_NE(text.out.find("forest"), std::string::npos);

  const auto json = run_command(program("tracer").string() + " scenes --format json");
  ASSERT_EQ(json.exit_code, 0) << json.err;
  const auto parsed = nlohmann::json::parse(json.out);
  EXPECT_EQ(parsed.at("default"), "sphereflake");
  ASSERT_EQ(parsed.at("scenes").size(), 3u);
  EXPECT_EQ(parsed.at("scenes")[1].at("name"), "mountain");
  EXPECT_EQ(parsed.at("scenes")[1].at("triangles"), 34050);

  EXPECT_EQ(run_command(program("tracer").string() + " scenes --format xml").exit_code, 2);
  const auto help = run_command(program("tracer").string() + " scenes --help");
  EXPECT_EQ(help.exit_code, 0);
  EXPECT_NE(help.out.find("--format"), std::string::npos);
}

}  // namespace
