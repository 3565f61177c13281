// --curve: the Mattson LRU stack against the Dinero-IV-exact engine, and the
// curve's points against `cachesim run` of each size on its own.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <fmt/format.h>

#include <random>

#include "nodetrace/cachesim/dinero/engine.hpp"
#include "nodetrace/cachesim/models/lru_stack.hpp"
#include "nodetrace/formats/write/trace_writer.hpp"
#include "test_support.hpp"

namespace nodetrace::cachesim {
namespace {

using testing::program;
using testing::run_command;

std::string quoted(const std::filesystem::path& path) { return fmt::format("'{}'", path.string()); }

// Blocks with locality: mostly near the previous one, sometimes anywhere.
std::vector<std::uint64_t> random_blocks(std::size_t count, std::uint64_t seed) {
  std::mt19937_64 random(seed);
  std::vector<std::uint64_t> blocks;
  std::uint64_t at = 0;
  for (std::size_t i = 0; i < count; ++i) {
    if (random() % 8 == 0) {
      at = random() % 4096;
    } else {
      at = (at + random() % 7) % 4096;
    }
    blocks.push_back(at);
  }
  return blocks;
}

TEST(LruStack, EveryFullyAssociativeSizeEqualsTheEngine) {
  for (const std::uint64_t seed : {1u, 2u, 3u}) {
    const auto blocks = random_blocks(30000, seed);
    LruStack stack;
    LruSizeCurve curve;
    for (const std::uint64_t block : blocks) curve.count(stack.access(block));
    for (unsigned log2_blocks = 0; log2_blocks <= 13; ++log2_blocks) {
      const std::uint64_t ways = std::uint64_t{1} << log2_blocks;
      CacheConfig cache;
      cache.size = ways * 8;
      cache.block_size = 8;
      cache.assoc = static_cast<std::uint32_t>(ways);
      Hierarchy hierarchy(single_level(cache));
      for (const std::uint64_t block : blocks) {
        formats::Record record;
        record.address = block * 8;
        record.size = 8;
        hierarchy.access(record);
      }
      hierarchy.finish();
      const Stats& stats = hierarchy.stats(1, CacheKind::Unified);
      EXPECT_EQ(curve.misses(log2_blocks), stats.demand_misses())
          << "seed " << seed << ", " << ways << " blocks";
      EXPECT_EQ(curve.references(), stats.demand_fetches());
    }
  }
}

// A stack renumbers its times as they grow: positions stay exact across it.
TEST(LruStack, PositionsAcrossRenumbering) {
  LruStack stack;
  for (std::uint64_t round = 0; round < 40000; ++round) {
    const std::uint64_t block = round % 3;  // 0 1 2 0 1 2 ...
    const std::uint64_t position = stack.access(block);
    EXPECT_EQ(position, round < 3 ? 0u : 3u) << round;
    if (position != (round < 3 ? 0u : 3u)) break;
  }
}

void write_tree_trace(const std::filesystem::path& path) {
  formats::WriterOptions options;
  options.form = formats::RecordForm::Din;
  options.records_per_data_frame = 512;
  auto writer = formats::TraceWriter::create(
      path.string(), {{"layout", {{"name", "bfl"}, {"node_size", 8}, {"node_base", 0}}}}, options);
  std::mt19937_64 random(7);
  for (std::uint64_t frame = 0; frame < 2; ++frame) {
    formats::AnimationFrameMarker marker;
    marker.frame = frame;
    marker.nodes_per_level = {1, 2, 4, 8, 16, 32, 64, 128, 256, 512};
    writer->begin_animation_frame(marker);
    for (int ray = 0; ray < 600; ++ray) {
      std::uint64_t slot = 0;
      for (formats::Tag level = 0; level < 10; ++level) {
        formats::Record record;
        record.address = 0x10000 + slot * 8;
        record.tag = level;
        writer->write(record);
        slot = 2 * slot + 1 + (random() & 1);
      }
    }
  }
  writer->finish();
}

std::vector<std::string> cells(const std::string& line) {
  std::vector<std::string> out;
  std::size_t from = 0;
  while (true) {
    const std::size_t comma = line.find(',', from);
    out.push_back(line.substr(from, comma - from));
    if (comma == std::string::npos) return out;
    from = comma + 1;
  }
}

// LRU's and opt's (MIN's layered stack for full, one MIN run per size for
// ways) alike.
TEST(CurveCommand, PointsEqualCachesimRunOfEachSize) {
  testing::TempDir dir;
  const auto trace = dir / "tree.din.zst";
  write_tree_trace(trace);
  const std::string cachesim = quoted(program("cachesim"));
  const auto curve = run_command(cachesim + " run " + quoted(trace) +
                                 " --curve --assoc 1,2,full --scheme single,split --policy lru,opt "
                                 "--split-level 4 --format csv");
  ASSERT_EQ(curve.exit_code, 0) << curve.err;
  std::size_t checked = 0;
  std::size_t at = curve.out.find('\n') + 1;
  EXPECT_EQ(curve.out.substr(0, at),
            "trace,scheme,block,assoc,policy,split_level,size,fetches,misses,miss_ratio\n");
  std::size_t largest = 0;
  while (at < curve.out.size()) {
    const std::size_t end = curve.out.find('\n', at);
    const auto point = cells(curve.out.substr(at, end - at));
    at = end + 1;
    ASSERT_EQ(point.size(), 10u);
    const std::uint64_t size = std::stoull(point[6]);
    largest = std::max<std::size_t>(largest, size);
    if (size > 8192) continue;  // every point up to 8k against its own run
    const bool split = point[1] == "split-low";
    const std::string options =
        split ? fmt::format("--scheme split --split-level 4 --high-policy cache --high-size 64 "
                            "--low-size {} --assoc {} --policy {}",
                            size, point[3], point[4])
              : fmt::format("--size {} --assoc {} --policy {}", size, point[3], point[4]);
    const auto run = run_command(cachesim + " run " + quoted(trace) + " " + options +
                                 " --format csv");
    ASSERT_EQ(run.exit_code, 0) << run.err;
    std::string line = run.out.substr(run.out.find('\n') + 1);
    if (!line.empty() && line.back() == '\n') line.pop_back();
    const auto row = cells(line);
    // low_refs / low_misses (one block per record), or fetches / misses.
    EXPECT_EQ(point[7], split ? row[17] : row[11]) << point[1] << " " << size << " " << point[3] << " " << point[4];
    EXPECT_EQ(point[8], split ? row[18] : row[12]) << point[1] << " " << size << " " << point[3] << " " << point[4];
    ++checked;
  }
  EXPECT_EQ(largest, std::size_t{64} << 20);
  EXPECT_GT(checked, 80u);
}

TEST(CurveCommand, HonoursFormatAndRefusesOptionsThatDoNotApply) {
  testing::TempDir dir;
  const auto trace = dir / "tree.din.zst";
  write_tree_trace(trace);
  const std::string cachesim = quoted(program("cachesim"));
  const auto json = run_command(cachesim + " run " + quoted(trace) + " --curve --assoc 1,full --format json");
  ASSERT_EQ(json.exit_code, 0) << json.err;
  const auto parsed = nlohmann::json::parse(json.out);
  EXPECT_EQ(parsed["columns"][0], "trace");
  ASSERT_FALSE(parsed["rows"].empty());
  EXPECT_TRUE(parsed["rows"][0]["size"].is_number());
  bool full = false;
  for (const auto& row : parsed["rows"]) full = full || row["assoc"] == "full";
  EXPECT_TRUE(full);
  for (const std::string option : {"--size 4k", "--per-level x.csv", "--low-size 4k", "--count-loads"}) {
    const auto refused = run_command(cachesim + " run " + quoted(trace) + " --curve " + option);
    EXPECT_EQ(refused.exit_code, 2) << option;
    EXPECT_NE(refused.err.find("cachesim run: " + option.substr(0, option.find(' ')) + " does not apply to --curve"),
              std::string::npos)
        << refused.err;
  }
}

}  // namespace
}  // namespace nodetrace::cachesim
