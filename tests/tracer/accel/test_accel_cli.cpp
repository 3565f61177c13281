// `--accel` end to end: BVH traces are byte-identical for 1 and 2 threads,
// written as extended din with the node's size, their header names the
// structure and tracetool info shows it; kd-tree headers keep no "accel".
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <string>

#include "nodetrace/formats/read/trace_reader.hpp"
#include "test_support.hpp"

namespace nodetrace::tracer {
namespace {

using nodetrace::testing::program;
using nodetrace::testing::read_file;
using nodetrace::testing::run_command;
using nodetrace::testing::TempDir;

std::string render(const std::string& options) {
  return program("tracer").string() + " render mountain:6 --width 40 --height 30 -q " + options;
}

TEST(AccelCliTest, BvhTraceIsByteIdenticalForOneAndTwoThreads) {
  TempDir dir;
  for (const std::string accel : {"bvh2", "cwbvh8"}) {
    const std::string common = render("--accel " + accel + " --high-size 2k ");
    ASSERT_EQ(run_command(common + "--threads 1 -o " + (dir / "one.xdin.zst").string()).exit_code, 0);
    ASSERT_EQ(run_command(common + "--threads 2 -o " + (dir / "two.xdin.zst").string()).exit_code, 0);
    const std::string one = read_file(dir / "one.xdin.zst");
    ASSERT_GT(one.size(), 1000u);
    EXPECT_TRUE(one == read_file(dir / "two.xdin.zst")) << accel;
  }
}

TEST(AccelCliTest, HeaderRecordsAndInfoNameTheStructure) {
  TempDir dir;
  const struct {
    const char* name;
    std::uint32_t node_size;
  } cases[] = {{"bvh2", 64}, {"bvh4", 128}, {"bvh8", 256}, {"cwbvh8", 80}};
  for (const auto& c : cases) {
    SCOPED_TRACE(c.name);
    // Standard output: no name to take the form from, so xdin by default.
    const auto path = dir / (std::string(c.name) + ".zst");
    const auto result = run_command(render("--accel " + std::string(c.name) + " --layout treelet -o - > " + path.string()));
    ASSERT_EQ(result.exit_code, 0) << result.err;
    auto reader = formats::TraceReader::open(path.string());
    const nlohmann::json& header = reader->header().json;
    EXPECT_EQ(header.at("records"), "xdin");
    EXPECT_EQ(header.at("accel").at("name"), c.name);
    EXPECT_EQ(header.at("accel").at("node_size"), c.node_size);
    EXPECT_EQ(header.at("layout").at("node_size"), c.node_size);
    EXPECT_EQ(header.at("layout").at("name"), "treelet");
    EXPECT_EQ(header.at("layout").at("treelet_bytes"), 64);
    EXPECT_FALSE(header.contains("kdtree"));
    formats::RecordBatch batch;
    std::uint64_t records = 0;
    std::vector<std::uint64_t> per_level;
    while (reader->next(batch)) {
      if (batch.marker) per_level = batch.marker->nodes_per_level;
      for (const auto& r : batch.records) {
        ASSERT_EQ(r.size, c.node_size);
        ASSERT_LT(r.tag, per_level.size());
        ++records;
      }
    }
    EXPECT_GT(records, 1000u);
    const auto info = run_command(program("tracetool").string() + " info " + path.string());
    ASSERT_EQ(info.exit_code, 0) << info.err;
    EXPECT_NE(info.out.find("accel                " + std::string(c.name) + "\n"), std::string::npos) << info.out;
  }
  // --node-size overrides the structure's size (what-if).
  const auto what_if = dir / "what-if.xdin.zst";
  ASSERT_EQ(run_command(render("--accel bvh2 --node-size 32 -o " + what_if.string())).exit_code, 0);
  EXPECT_EQ(formats::TraceReader::open(what_if.string())->header().json.at("accel").at("node_size"), 32);
}

TEST(AccelCliTest, KdTreeHeaderHasNoAccelKeyButInfoNamesIt) {
  TempDir dir;
  const auto path = dir / "kd.din.zst";
  ASSERT_EQ(run_command(render("-o " + path.string())).exit_code, 0);
  EXPECT_FALSE(formats::TraceReader::open(path.string())->header().json.contains("accel"));
  const auto info = run_command(program("tracetool").string() + " info " + path.string());
  EXPECT_NE(info.out.find("accel                kdtree\n"), std::string::npos) << info.out;
}

TEST(AccelCliTest, InfoGivesTheSameKdTreeForAnyBuildThreadsAndItsBuildCpuTime) {
  auto kdtree_with = [](const std::string& threads) {
    const auto info = run_command(program("tracer").string() + " info mountain --format json --threads " + threads);
    EXPECT_EQ(info.exit_code, 0) << info.err;
    return nlohmann::json::parse(info.out).at("kdtree");
  };
  const auto one = kdtree_with("1"), three = kdtree_with("3");
  for (const char* key : {"nodes", "leaves", "empty_leaves", "nodes_per_level", "sah_cost"}) {
    EXPECT_EQ(one.at(key), three.at(key)) << key;
  }
  EXPECT_GT(one.at("build_cpu_seconds").get<double>(), 0);
  const auto too_many = run_command(program("tracer").string() + " info mountain --threads 100000");
  EXPECT_EQ(too_many.exit_code, 2);
  EXPECT_NE(too_many.err.find("--threads 100000"), std::string::npos) << too_many.err;
}

TEST(AccelCliTest, InfoPrintsThePeakMemoryOfLoadingAndBuilding) {
  const auto json = run_command(program("tracer").string() + " info mountain:7 --format json");
  ASSERT_EQ(json.exit_code, 0) << json.err;
  const auto info = nlohmann::json::parse(json.out);
  const auto bytes = info.at("peak_memory").at("bytes").get<std::uint64_t>();
  const auto triangles = info.at("scene").at("triangles").get<std::uint64_t>();
  EXPECT_GT(bytes, std::uint64_t{1} << 20) << "a process holding a scene and a tree";
  EXPECT_DOUBLE_EQ(info.at("peak_memory").at("bytes_per_triangle").get<double>(), double(bytes) / double(triangles));
  const auto text = run_command(program("tracer").string() + " info mountain:7");
  EXPECT_NE(text.out.find("peak memory: "), std::string::npos) << text.out;
  EXPECT_NE(text.out.find(" bytes per triangle), the scene loaded and its kd-tree built"), std::string::npos)
      << text.out;
}

TEST(AccelCliTest, DinNameForABvhIsRefusedUnlessDinIsAsked) {
  TempDir dir;
  const auto refused = run_command(render("--accel bvh2 -o " + (dir / "t.din.zst").string()));
  EXPECT_EQ(refused.exit_code, 2);
  EXPECT_NE(refused.err.find("xdin"), std::string::npos) << refused.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "t.din.zst"));
  EXPECT_EQ(run_command(render("--accel bvh2 --records din -o " + (dir / "t.din.zst").string())).exit_code, 0);
}

TEST(AccelCliTest, InfoShowsTheStructuresFigures) {
  const auto info = run_command(program("tracer").string() + " info mountain:6 --accel bvh4 --format json");
  ASSERT_EQ(info.exit_code, 0) << info.err;
  const auto j = nlohmann::json::parse(info.out);
  const auto& a = j.at("accel");
  EXPECT_EQ(a.at("name"), "bvh4");
  EXPECT_EQ(a.at("node_size"), 128);
  EXPECT_EQ(a.at("bytes"), a.at("nodes").get<std::uint64_t>() * 128);
  std::uint64_t sum = 0;
  for (const auto& n : a.at("nodes_per_level")) sum += n.get<std::uint64_t>();
  EXPECT_EQ(sum, a.at("nodes").get<std::uint64_t>());
  EXPECT_GT(a.at("sah_cost").get<double>(), 0);
  EXPECT_GT(a.at("mean_leaf_size").get<double>(), 0);
  EXPECT_TRUE(a.contains("build_seconds"));
  std::uint64_t leaves = 0;
  for (const auto& [size, count] : a.at("leaves_by_size").items()) {
    EXPECT_LE(std::stoul(size), 4u);  // the default largest leaf
    leaves += count.get<std::uint64_t>();
  }
  EXPECT_EQ(leaves, a.at("leaves").get<std::uint64_t>());
}

}  // namespace
}  // namespace nodetrace::tracer
