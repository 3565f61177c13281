// `tracer render` and `tracer info` end to end: traces are byte-identical for
// 1 and 2 threads, the header and markers carry what docs/ARCHITECTURE.md lists, and
// bad usage exits 2.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <map>
#include <string>

#include "nodetrace/formats/read/trace_reader.hpp"
#include "test_support.hpp"

namespace nodetrace::tracer {
namespace {

using nodetrace::testing::program;
using nodetrace::testing::run_command;
using nodetrace::testing::TempDir;

const std::string kScene = "mountain:6";  // a small built-in scene with mirror and glass

std::string tracer() { return program("tracer").string(); }

TEST(RenderCliTest, TraceIsByteIdenticalForOneAndTwoThreads) {
  TempDir dir;
  const std::string common = tracer() + " render " + kScene + " --width 48 --height 36 -q --high-size 1k ";
  ASSERT_EQ(run_command(common + "--threads 1 -o " + (dir / "one.din.zst").string()).exit_code, 0);
  ASSERT_EQ(run_command(common + "--threads 2 -o " + (dir / "two.din.zst").string()).exit_code, 0);
  const std::string one = nodetrace::testing::read_file(dir / "one.din.zst");
  ASSERT_GT(one.size(), 1000u);
  EXPECT_TRUE(one == nodetrace::testing::read_file(dir / "two.din.zst"));
}

TEST(RenderCliTest, ArchiveWritesTheSameRecordsAndExcludesALevel) {
  TempDir dir;
  const std::string common = tracer() + " render " + kScene + " --width 48 --height 36 -q --high-size 1k ";
  ASSERT_EQ(run_command(common + "-o " + (dir / "default.din.zst").string()).exit_code, 0);
  const auto archived = run_command(common + "--archive -o " + (dir / "archive.din.zst").string());
  ASSERT_EQ(archived.exit_code, 0) << archived.err;
  auto archive = formats::TraceReader::open((dir / "archive.din.zst").string());
  auto original = formats::TraceReader::open((dir / "default.din.zst").string());
  EXPECT_EQ(archive->header().json.at("compression"), nlohmann::json({{"level", 17}, {"window_log", 26}}));
  EXPECT_EQ(archive->trailer()->record_hash, original->trailer()->record_hash);
  EXPECT_EQ(archive->trailer()->totals.at("records"), original->trailer()->totals.at("records"));
  EXPECT_EQ(run_command("zstd -dc " + (dir / "archive.din.zst").string()).out,
            run_command("zstd -dc " + (dir / "default.din.zst").string()).out);
  const auto both = run_command(common + "--archive --zstd-level 5 -o " + (dir / "x.din.zst").string());
  EXPECT_EQ(both.exit_code, 2);
  EXPECT_NE(both.err.find("--archive"), std::string::npos) << both.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "x.din.zst"));
}

TEST(RenderCliTest, HeaderMarkersAndRecordsFollowTheDesign) {
  TempDir dir;
  const auto path = dir / "t.xdin.zst";
  const auto result = run_command(tracer() + " render " + kScene +
                                  " --width 40 --height 30 --max-depth 4 --pixel-order morton"
                                  " --layout hybrid --split-level 5 --node-base 0x100000 -o " +
                                  path.string());
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(result.err.find("node fetches"), std::string::npos);  // summary on stderr

  auto reader = formats::TraceReader::open(path.string());
  const nlohmann::json& h = reader->header().json;
  EXPECT_EQ(h["producer"]["tool"], "tracer");
  EXPECT_EQ(h["scene"]["name"], "mountain");
  EXPECT_GT(h["scene"]["triangles"].get<int>(), 1000);
  EXPECT_FALSE(h["scene"]["hash"].get<std::string>().empty());
  EXPECT_EQ(h["render"]["width"], 40);
  EXPECT_EQ(h["render"]["height"], 30);
  EXPECT_EQ(h["render"]["max_depth"], 4);
  EXPECT_EQ(h["render"]["pixel_order"], "morton");
  EXPECT_EQ(h["render"]["frames"], 1);
  EXPECT_EQ(h["layout"]["name"], "hybrid");
  EXPECT_EQ(h["layout"]["split_level"], 5);
  EXPECT_EQ(h["layout"]["node_size"], 8);
  EXPECT_EQ(h["layout"]["node_base"], 0x100000);
  EXPECT_EQ(h["rays"]["cast"].front(), "primary");
  EXPECT_EQ(h["records"], "xdin");
  EXPECT_EQ(h["tag"], "node-level");
  // Only inputs that change the records: no threads, paths or times.
  const std::string text = h.dump();
  EXPECT_EQ(text.find("thread"), std::string::npos);
  EXPECT_EQ(text.find(dir.path().string()), std::string::npos);
  EXPECT_EQ(text.find("seconds"), std::string::npos);

  formats::RecordBatch batch;
  std::uint64_t records = 0, markers = 0, root_fetches = 0;
  std::uint64_t nodes = 0;
  while (reader->next(batch)) {
    if (batch.marker) {
      ++markers;
      std::uint64_t sum = 0;
      for (auto n : batch.marker->nodes_per_level) sum += n;
      EXPECT_EQ(sum, batch.marker->nodes);
      EXPECT_EQ(batch.marker->depth + 1, batch.marker->nodes_per_level.size());
      nodes = batch.marker->nodes;
    }
    for (const auto& r : batch.records) {
      ++records;
      ASSERT_TRUE(formats::is_level(r.tag));
      ASSERT_EQ(r.size, 8u);
      ASSERT_GE(r.address, 0x100000u);
      ASSERT_LT(r.address, 0x100000u + nodes * 8);
      ASSERT_EQ(r.address % 8, 0u);
      if (r.tag == 0) {
        ++root_fetches;
        ASSERT_EQ(r.address, 0x100000u);  // the root is slot 0 of every layout
      }
    }
  }
  EXPECT_EQ(markers, 1u);
  EXPECT_GT(records, 40u * 30u);
  ASSERT_TRUE(reader->trailer().has_value());
  const auto& totals = reader->trailer()->totals;
  EXPECT_EQ(totals["node_fetches"].get<std::uint64_t>(), records);
  EXPECT_EQ(totals["rays"]["primary"].get<std::uint64_t>(), 40u * 30u);
  EXPECT_LE(root_fetches, totals["rays"]["primary"].get<std::uint64_t>() +
                              totals["rays"]["shadow"].get<std::uint64_t>() +
                              totals["rays"]["reflection"].get<std::uint64_t>() +
                              totals["rays"]["refraction"].get<std::uint64_t>());
}

TEST(RenderCliTest, OptionalStreamsAreTaggedPAndT) {
  TempDir dir;
  const auto path = dir / "s.xdin.zst";
  ASSERT_EQ(run_command(tracer() + " render " + kScene + " --width 16 --height 12 -q --streams nodes,lists,triangles -o " +
                        path.string()).exit_code, 0);
  auto reader = formats::TraceReader::open(path.string());
  formats::RecordBatch batch;
  std::uint64_t lists = 0, triangles = 0, nodes = 0;
  while (reader->next(batch)) {
    for (const auto& r : batch.records) {
      if (r.tag == formats::kTagPrimitiveList) ++lists;
      else if (r.tag == formats::kTagTriangle) ++triangles;
      else if (formats::is_level(r.tag)) ++nodes;
    }
  }
  EXPECT_GT(nodes, 0u);
  EXPECT_GT(triangles, 0u);
  EXPECT_EQ(lists, triangles);  // one index read per triangle test
}

TEST(RenderCliTest, RunOfAnimationFramesHasOneMarkerEach) {
  NODETRACE_SHARED_OR_SKIP(shared);
  const auto robot = shared / "scenes/bart/robots/Robot.aff";
  TempDir dir;
  const auto path = dir / "r.din.zst";
  const auto result = run_command(tracer() + " render " + robot.string() +
                                  " --width 16 --height 12 --frames 3-4 --high-size 2k -q -o " + path.string());
  ASSERT_EQ(result.exit_code, 0) << result.err;
  auto reader = formats::TraceReader::open(path.string());
  EXPECT_EQ(reader->header().json["render"]["frames"], 2);
  EXPECT_EQ(reader->header().json["scene"]["name"], "Robot.aff");
  formats::RecordBatch batch;
  std::vector<std::uint64_t> frames;
  while (reader->next(batch)) {
    if (batch.marker) {
      frames.push_back(batch.marker->frame);
      EXPECT_TRUE(batch.marker->extra.contains("split_level"));
    }
  }
  EXPECT_EQ(frames, (std::vector<std::uint64_t>{3, 4}));
}

TEST(RenderCliTest, BadUsageExitsTwoAndBadSceneOne) {
  TempDir dir;
  const std::string out = " -o " + (dir / "x.din.zst").string();
  EXPECT_EQ(run_command(tracer() + " render --help").exit_code, 0);
  EXPECT_EQ(run_command(tracer() + " info --help").exit_code, 0);
  auto r = run_command(tracer() + " render " + kScene + " --layout hybrid" + out);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--split-level"), std::string::npos) << r.err;
  EXPECT_EQ(run_command(tracer() + " render " + kScene + " --frames 0-3" + out).exit_code, 2);
  EXPECT_EQ(run_command(tracer() + " render " + kScene + " --streams nodes,leaves" + out).exit_code, 2);
  EXPECT_EQ(run_command(tracer() + " render " + kScene + " --high-size 4q" + out).exit_code, 2);
  EXPECT_EQ(run_command(tracer() + " render " + kScene + " --layout zigzag" + out).exit_code, 2);
  EXPECT_EQ(run_command(tracer() + " render " + kScene + " --width 0" + out).exit_code, 2);
  EXPECT_EQ(run_command(tracer() + " info").exit_code, 2);
  EXPECT_EQ(run_command(tracer() + " render " + (dir / "missing.obj").string() + out).exit_code, 1);
  EXPECT_FALSE(std::filesystem::exists(dir / "x.din.zst"));
}

TEST(RenderCliTest, ImageIsAPngAndRenderOnlyWritesNoTrace) {
  TempDir dir;
  const auto png = dir / "i.png";
  const auto r = run_command(tracer() + " render " + kScene + " --width 24 --height 18 --time 0 --pixel-order tiled --image " +
                             png.string() + " --eye 0 5 20 --look-at 0 0 0 --fov 50");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string bytes = nodetrace::testing::read_file(png);
  ASSERT_GT(bytes.size(), 8u);
  EXPECT_EQ(bytes.substr(1, 3), "PNG");
  EXPECT_NE(r.err.find("0 records"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "i.png.tmp"));
}

// Issue 52 item 6: the header's camera.fov is the field of view the rays
// use, which --fov sets beside --eye and --look-at (it said 45, the default).
TEST(RenderCliTest, HeaderCameraFovIsTheOneTheRaysUse) {
  TempDir dir;
  const std::string common = tracer() + " render " + kScene + " --width 16 --height 12 -q --eye 0 5 20 --look-at 0 0 0";
  std::map<std::string, std::string> text;
  for (const std::string fov : {"20", "45"}) {
    const auto path = dir / ("fov" + fov + ".din.zst");
    const auto r = run_command(common + " --fov " + fov + " -o " + path.string());
    ASSERT_EQ(r.exit_code, 0) << r.err;
    auto reader = formats::TraceReader::open(path.string());
    const nlohmann::json& render = reader->header().json.at("render");
    EXPECT_EQ(render.at("camera").at("fov"), std::stod(fov)) << render.dump();
    EXPECT_EQ(render.at("fov"), std::stod(fov)) << render.dump();
    text[fov] = run_command("zstd -dc " + path.string()).out;
  }
  // The two fields of view give other rays, so other records.
  EXPECT_NE(text["20"], text["45"]);
}

TEST(RenderCliTest, InfoReportsTreeAndRayKinds) {
  const auto r = run_command(tracer() + " info " + kScene + " --format json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["scene"]["name"], "mountain");
  EXPECT_GT(j["kdtree"]["nodes"].get<int>(), 1000);
  EXPECT_EQ(j["kdtree"]["nodes_per_level"][0], 1);
  EXPECT_EQ(j["rays"]["primary"], "cast");
  EXPECT_TRUE(j["kdtree"]["split_level_for_high_size"].contains("4096"));
}

// Issue 22 items 8-11, 13: outputs checked before the render, one-frame info,
// the depth limit used recorded.
TEST(RenderCliTest, EmptyOutputNameIsAUsageError) {
  for (const std::string option : {"-o ''", "--image ''"}) {
    const auto r = run_command(tracer() + " render " + kScene + " --width 4 --height 3 " + option);
    EXPECT_EQ(r.exit_code, 2) << option;
    EXPECT_NE(r.err.find("tracer render: "), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(": an empty name: give a file name"), std::string::npos) << r.err;
  }
}

TEST(RenderCliTest, MissingOutputFolderFailsBeforeRendering) {
  TempDir dir;
  const auto r = run_command(tracer() + " render " + kScene + " --width 4 --height 3 -o " +
                             (dir / "t.din.zst").string() + " --image " + (dir / "nodir" / "x.png").string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("tracer render: " + (dir / "nodir" / "x.png").string() +
                       ": cannot write: folder '" + (dir / "nodir").string() + "' does not exist (checked before rendering)"),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "t.din.zst"));  // nothing rendered, nothing written
}

TEST(RenderCliTest, DirectoryAsSceneSaysItIsADirectory) {
  TempDir dir;
  const auto r = run_command(tracer() + " render " + dir.path().string() + "/");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find(": is a directory, not a scene file"), std::string::npos) << r.err;
}

TEST(RenderCliTest, InfoDoesNotOfferFrames) {
  const auto help = run_command(tracer() + " info --help");
  ASSERT_EQ(help.exit_code, 0);
  EXPECT_EQ(help.out.find("--frames"), std::string::npos) << help.out;
  EXPECT_NE(help.out.find("--frame"), std::string::npos) << help.out;
}

TEST(RenderCliTest, HeaderRecordsTheDepthLimitUsed) {
  TempDir dir;
  const auto trace = dir / "t.din.zst";
  ASSERT_EQ(run_command(tracer() + " render " + kScene + " --width 4 --height 3 --quiet -o " + trace.string()).exit_code,
            0);
  auto reader = formats::TraceReader::open(trace.string());
  const nlohmann::json kdtree = reader->header().json.at("kdtree");
  const auto info = nlohmann::json::parse(run_command(tracer() + " info " + kScene + " --format json").out);
  EXPECT_GT(kdtree.at("max_depth").get<int>(), 0);
  EXPECT_EQ(kdtree.at("max_depth"), info["kdtree"]["depth_limit"]) << info["kdtree"].dump();
  EXPECT_TRUE(kdtree.contains("max_depth_default"));
  const auto given = dir / "given.din.zst";
  ASSERT_EQ(run_command(tracer() + " render " + kScene + " --width 4 --height 3 --quiet --tree-depth 12 -o " +
                        given.string()).exit_code,
            0);
  const nlohmann::json fixed = formats::TraceReader::open(given.string())->header().json.at("kdtree");
  EXPECT_EQ(fixed.at("max_depth"), 12);
  EXPECT_FALSE(fixed.contains("max_depth_default"));
}

}  // namespace
}  // namespace nodetrace::tracer
