// One render, several layouts (`--layout a,b --high-size x,y -o NAME{layout}`):
// each trace equals, byte for byte, the one a render with that layout alone
// writes, and the option combinations that cannot work are usage errors.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "test_support.hpp"

namespace nodetrace::tracer {
namespace {

using nodetrace::testing::program;
using nodetrace::testing::read_file;
using nodetrace::testing::run_command;
using nodetrace::testing::TempDir;

std::string tracer() { return program("tracer").string(); }

// Renders `common` once with every layout, then once per layout, and
// compares the files. `layouts` are the names {layout} takes, each with the
// options that ask for it alone.
void expect_each_layout_as_rendered_alone(const std::string& common, const std::string& several,
                                          const std::vector<std::pair<std::string, std::string>>& layouts,
                                          const std::string& suffix) {
  TempDir dir;
  const auto together = run_command(common + " " + several + " -o " + (dir / ("{layout}" + suffix)).string());
  ASSERT_EQ(together.exit_code, 0) << together.err;
  for (const auto& [name, alone] : layouts) {
    const auto path = dir / ("alone-" + name + suffix);
    const auto result = run_command(common + " " + alone + " -o " + path.string());
    ASSERT_EQ(result.exit_code, 0) << result.err;
    const std::string expected = read_file(path);
    ASSERT_GT(expected.size(), 200u) << name;
    EXPECT_TRUE(read_file(dir / (name + suffix)) == expected) << name << " differs from its own render";
  }
}

const std::vector<std::pair<std::string, std::string>> kEveryLayout = {
    {"dfl", "--layout dfl"},
    {"bfl", "--layout bfl"},
    {"veb", "--layout veb"},
    {"treelet", "--layout treelet"},
    {"hybrid-k3", "--split-level 3"},
    {"hybrid-k7", "--split-level 7"},
};

TEST(LayoutTraces, EachContainerTraceEqualsItsOwnRenderWithEveryStream) {
  expect_each_layout_as_rendered_alone(
      tracer() + " render mountain:6 --width 32 --height 24 -q --threads 2 --streams nodes,lists,triangles",
      "--layout dfl,hybrid,bfl,veb,treelet --split-level 3,7", kEveryLayout, ".xdin.zst");
}

TEST(LayoutTraces, EachBvhTraceEqualsItsOwnRender) {
  expect_each_layout_as_rendered_alone(
      tracer() + " render mountain:6 --width 24 --height 16 -q --accel cwbvh8 --treelet-bytes 256",
      "--layout treelet,bfl,hybrid --split-level 2",
      {{"treelet", "--layout treelet"}, {"bfl", "--layout bfl"}, {"hybrid-k2", "--split-level 2"}}, ".xdin.zst");
}

TEST(LayoutTraces, EachTraceOfRaysInFlightOnSeveralUnitsEqualsItsOwnRender) {
  expect_each_layout_as_rendered_alone(
      tracer() + " render mountain:6 --width 24 --height 16 -q --rays-in-flight 4 --units 2 --unit-pixels 16",
      "--layout veb,hybrid --split-level 4", {{"veb", "--layout veb"}, {"hybrid-k4", "--split-level 4"}},
      ".din.zst");
}

TEST(LayoutTraces, EachPlainTraceEqualsItsOwnRenderAtHighSizes) {
  expect_each_layout_as_rendered_alone(tracer() + " render mountain:6 --width 24 --height 16 -q",
                                       "--layout hybrid,dfl --high-size 512,2k",
                                       {{"hybrid-512", "--high-size 512"},
                                        {"hybrid-2k", "--high-size 2k"},
                                        {"dfl", "--layout dfl"}},
                                       ".din");
}

TEST(LayoutTraces, SampledRenderWritesTheSameWindowsInEachLayout) {
  expect_each_layout_as_rendered_alone(
      tracer() + " render mountain:6 --width 32 --height 32 -q --sample-rows 1/4 --sample-seed 3",
      "--layout bfl,hybrid --split-level 5", {{"bfl", "--layout bfl"}, {"hybrid-k5", "--split-level 5"}},
      ".din.zst");
}

// Two animation frames whose trees differ: the layouts (and the hybrid's K
// from the high size) are made per frame.
TEST(LayoutTraces, EveryAnimationFrameIsRelaidOut) {
  TempDir dir;
  nodetrace::testing::write_two_frame_scene(dir.path(), 12);
  expect_each_layout_as_rendered_alone(
      tracer() + " render " + (dir / "moving.aff").string() + " --frames 0-1 --width 24 --height 16 -q",
      "--layout dfl,hybrid --high-size 128", {{"dfl", "--layout dfl"}, {"hybrid-128", "--high-size 128"}},
      ".din.zst");
}

TEST(LayoutTraces, CombinationsThatCannotWorkAreUsageErrors) {
  TempDir dir;
  const std::string common = tracer() + " render mountain:6 --width 8 --height 8 -q ";
  const auto expect_usage_error = [&](const std::string& options, const std::string& says) {
    const auto result = run_command(common + options);
    EXPECT_EQ(result.exit_code, 2) << options << "\n" << result.err;
    EXPECT_NE(result.err.find(says), std::string::npos) << options << "\n" << result.err;
  };
  const std::string out = (dir / "t.din.zst").string();
  expect_usage_error("--layout dfl,bfl -o " + out, "needs {layout} in the file name");
  expect_usage_error("--layout dfl,bfl", "2 layouts (dfl, bfl) and nothing takes their records: give -o with "
                                         "{layout} in the file name (one trace each), --simulate or --trace-info");
  expect_usage_error("--layout dfl,bfl --trace-info " + (dir / "ti.json").string(),
                     "2 layouts: --trace-info needs {layout} in the file name");
  expect_usage_error("--layout dfl,bfl -o '{layout}' --discard-records", "--discard-records");
  expect_usage_error("--layout dfl,dfl -o " + (dir / "{layout}.din").string(), "--output names the same file twice");
  expect_usage_error("--layout dfl,bfl --split-level 4 -o " + (dir / "{layout}.din").string(),
                     "apply to --layout hybrid only");
  expect_usage_error("--layout hybrid,dfl -o " + (dir / "{layout}.din").string(), "needs --split-level K");
  expect_usage_error("--split-level 3 --high-size 1k -o " + out, "needs {layout} in the file name");
  EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
}

// Issue 47: without -o, several layouts were refused for -o's missing
// {layout}. -o names no file then: the records go to the other outputs.
TEST(LayoutTraces, WithoutOutputSeveralLayoutsGoToTheirOtherOutputs) {
  TempDir dir;
  const std::string common = tracer() + " render mountain:6 --width 8 --height 8 -q --high-size 2k,4k ";
  const auto info = run_command(common + "--trace-info " + (dir / "ti-{layout}.json").string());
  ASSERT_EQ(info.exit_code, 0) << info.err;
  EXPECT_NE(read_file(dir / "ti-hybrid-2k.json").find("\"header\""), std::string::npos);
  EXPECT_NE(read_file(dir / "ti-hybrid-4k.json").find("\"header\""), std::string::npos);
  const auto discarded = run_command(common + "--discard-records");
  EXPECT_EQ(discarded.exit_code, 2);
  EXPECT_NE(discarded.err.find("--discard-records writes no trace: it takes one layout"), std::string::npos)
      << discarded.err;
  const auto alone = run_command(common);
  EXPECT_EQ(alone.exit_code, 2);
  EXPECT_EQ(alone.err.find("-o needs"), std::string::npos) << alone.err;
  EXPECT_NE(alone.err.find("2 layouts (hybrid-2k, hybrid-4k) and nothing takes their records"), std::string::npos)
      << alone.err;
}

TEST(LayoutTraces, OneLayoutMayNameItsFileByTheLayout) {
  TempDir dir;
  const auto result = run_command(tracer() + " render mountain:6 --width 8 --height 8 -q --split-level 4 -o " +
                                  (dir / "m-{layout}.din").string());
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_TRUE(std::filesystem::exists(dir / "m-hybrid-k4.din"));
}

}  // namespace
}  // namespace nodetrace::tracer
