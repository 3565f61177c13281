// open_scene dispatch and `tracer scenes`.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <sys/stat.h>

#include <fstream>
#include <string>
#include <thread>

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

// A regular file is read in one piece of its size, anything else (a FIFO,
// a shell's <(...)) to its end: both give the same scene.
TEST(SceneLoader, AnObjFromAPipeLoadsAsFromAFile) {
  TempDir dir;
  std::string text;
  for (int i = 0; i < 6000; ++i) {  // about 150 KB: more than a pipe holds at once
    text += "v " + std::to_string(i) + " " + (i % 3 == 1 ? "1" : "0") + " 0.5\n";  // no triangle flat
  }
  for (int i = 1; i + 2 <= 6000; i += 3) {
    text += "f " + std::to_string(i) + " " + std::to_string(i + 1) + " " + std::to_string(i + 2) + "\n";
  }
  write_file(dir / "file.obj", text);
  const auto fifo = dir / "pipe.obj";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  std::thread writer([&] { std::ofstream(fifo, std::ios::binary) << text; });
  const auto from_pipe = open_scene(fifo.string());
  writer.join();
  const auto from_file = open_scene((dir / "file.obj").string());

  EXPECT_EQ(from_pipe->content_hash(), from_file->content_hash());
  const auto pipe_triangles = from_pipe->at_time(0).triangles;
  const auto file_triangles = from_file->at_time(0).triangles;
  ASSERT_EQ(file_triangles.size(), 2000u);
  ASSERT_EQ(pipe_triangles.size(), file_triangles.size());
  for (std::size_t t = 0; t < file_triangles.size(); ++t) {
    EXPECT_EQ(pipe_triangles[t].v2.x, file_triangles[t].v2.x) << t;
    EXPECT_EQ(pipe_triangles[t].v2.y, file_triangles[t].v2.y) << t;
  }
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
