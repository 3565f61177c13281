// `cachesim run` end to end: containers with animation-frame markers, K = auto,
// several traces, standard input, exit codes, and equality with `cachesim
// dinero` for single caches.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include "nodetrace/cachesim/wrap/wrap.hpp"
#include "nodetrace/formats/write/trace_writer.hpp"
#include "test_support.hpp"

namespace nodetrace::cachesim {
namespace {

using testing::program;
using testing::run_command;

std::string quoted(const std::filesystem::path& path) { return fmt::format("'{}'", path.string()); }

std::string cachesim() { return quoted(program("cachesim")); }

// A two-frame container: a complete tree of 4 levels in BFL order at 0x1000
// (15 nodes), each frame visiting it root to leaf for 200 rays.
void write_two_frame_container(const std::filesystem::path& path, std::uint32_t layout_split,
                               const std::vector<std::vector<std::uint64_t>>& trees = {
                                   {1, 2, 4, 8}, {1, 2, 4, 8}}) {
  formats::WriterOptions options;
  options.form = formats::RecordForm::Din;
  options.records_per_data_frame = 256;
  nlohmann::json header = {{"layout", {{"name", "bfl"}, {"split_level", layout_split},
                                       {"node_size", 8}, {"node_base", 4096}}}};
  auto writer = formats::TraceWriter::create(path.string(), header, options);
  for (std::uint64_t frame = 0; frame < 2; ++frame) {
    formats::AnimationFrameMarker marker;
    marker.frame = frame;
    marker.nodes_per_level = trees.at(frame);
    marker.nodes = 15;
    marker.leaves = 8;
    marker.depth = 4;
    writer->begin_animation_frame(marker);
    for (std::uint64_t ray = 0; ray < 200; ++ray) {
      std::uint64_t slot = 0;
      for (formats::Tag level = 0; level < 4; ++level) {
        formats::Record record;
        record.address = 0x1000 + slot * 8;
        record.size = 8;
        record.tag = level;
        writer->write(record);
        slot = 2 * slot + 1 + ((ray >> level) & 1);
      }
      // Some far-away low-level data so the low cache misses.
      formats::Record far;
      far.address = 0x100000 + ((ray * 72) % 4096);
      far.tag = 5;
      writer->write(far);
    }
  }
  writer->finish();
}

TEST(SweepCommand, AutoSplitLevelFromContainerMarkersAndLayoutNote) {
  testing::TempDir dir;
  write_two_frame_container(dir / "tree.din.zst", 3);
  // High cache 32 bytes: levels 0, 1 (3 nodes, 24 bytes) fit, level 2 does not: K = 2.
  const auto result = run_command(cachesim() + " run " + quoted(dir / "tree.din.zst") +
                                  " --size 64 --scheme split --split-level auto --format csv");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(result.out.find(",split,64,8,1,lru,retain,32,32,2,2000,2000,"), std::string::npos)
      << result.out;
  // 3 high blocks loaded in each of the 2 frames.
  EXPECT_NE(result.out.find(",800,0,6,1200,"), std::string::npos) << result.out;
  EXPECT_NE(result.err.find("split level 2 (auto) differs from the layout's split_level 3"),
            std::string::npos)
      << result.err;
}

std::vector<std::vector<std::string>> csv_table(const std::string& text) {
  std::vector<std::vector<std::string>> rows;
  std::size_t at = 0;
  while (at < text.size()) {
    const std::size_t end = text.find('\n', at);
    const std::string line = text.substr(at, end - at);
    at = end == std::string::npos ? text.size() : end + 1;
    if (line.empty()) break;
    std::vector<std::string> cells;
    std::size_t from = 0;
    while (true) {
      const std::size_t comma = line.find(',', from);
      cells.push_back(line.substr(from, comma - from));
      if (comma == std::string::npos) break;
      from = comma + 1;
    }
    rows.push_back(std::move(cells));
  }
  return rows;
}

// Frame 0's tree {1, 2, 4, 8}: levels 0-2 (56 bytes) fit a 64-byte high
// cache, K = 3; frame 1's tree {1, 2, 8, 8}: levels 0-1 only, K = 2.
TEST(SweepCommand, PerFrameRowsSumToTheTotalsAndUseEachFramesK) {
  testing::TempDir dir;
  write_two_frame_container(dir / "tree.din.zst", 3, {{1, 2, 4, 8}, {1, 2, 8, 8}});
  const auto result = run_command(cachesim() + " run " + quoted(dir / "tree.din.zst") +
                                  " --size 64,128 --scheme single,split --split-level auto "
                                  "--high-policy retain,cache --per-frame " + quoted(dir / "frames.csv") +
                                  " --format csv");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  // Two outputs, one table each: the totals on standard output, the frames in their file.
  EXPECT_EQ(result.out.find("\n\n"), std::string::npos) << result.out;
  const auto totals = csv_table(result.out);
  const auto frames = csv_table(testing::read_file(dir / "frames.csv"));
  ASSERT_EQ(totals.size(), 1u + 6u);
  ASSERT_EQ(frames.size(), 1u + 2u * 6u);
  std::vector<std::string> frame_header = totals[0];
  frame_header.insert(frame_header.begin() + 1, "frame");
  EXPECT_EQ(frames[0], frame_header);
  const std::vector<std::string> counted{"refs",        "fetches",    "misses",   "high_refs",
                                         "high_misses", "high_loads", "low_refs", "low_misses"};
  auto column = [&](const std::string& name) {
    return static_cast<std::size_t>(
        std::find(totals[0].begin(), totals[0].end(), name) - totals[0].begin());
  };
  for (std::size_t config = 0; config < 6; ++config) {
    const auto& total = totals[1 + config];
    const auto& first = frames[1 + config];       // frame 0 rows come first
    const auto& second = frames[1 + 6 + config];  // then frame 1's
    EXPECT_EQ(first[1], "0");
    EXPECT_EQ(second[1], "1");
    for (const std::string& name : counted) {
      const std::size_t c = column(name);
      if (total[c].empty()) {
        EXPECT_TRUE(first[c + 1].empty() && second[c + 1].empty()) << name;
        continue;
      }
      EXPECT_EQ(std::stoull(first[c + 1]) + std::stoull(second[c + 1]), std::stoull(total[c]))
          << "configuration " << config << ", " << name;
    }
    if (total[column("scheme")] == "split" && total[column("high_size")] == "64") {
      EXPECT_EQ(first[column("split_level") + 1], "3");
      EXPECT_EQ(second[column("split_level") + 1], "2");
      EXPECT_EQ(total[column("split_level")], "3");  // the first frame's
      // Frame 0 loads its 7 level 0-2 blocks, frame 1 its 3 level 0-1 blocks.
      if (total[column("high_policy")] == "retain") {
        EXPECT_EQ(first[column("high_loads") + 1], "7");
        EXPECT_EQ(second[column("high_loads") + 1], "3");
      }
    }
  }
  EXPECT_NE(result.err.find("split level (auto) from 2 to 3 over 2 animation frames"),
            std::string::npos)
      << result.err;
  // JSON: each output the same object shape, {"columns", "rows"}; `-` puts the frames alone on stdout.
  const auto json_run = run_command(cachesim() + " run " + quoted(dir / "tree.din.zst") +
                                    " --size 128 --scheme split --per-frame - --format json");
  ASSERT_EQ(json_run.exit_code, 0) << json_run.err;
  const auto json = nlohmann::json::parse(json_run.out);
  ASSERT_EQ(json["rows"].size(), 2u);
  EXPECT_EQ(json["columns"][1], "frame");
  EXPECT_EQ(json["rows"][1]["frame"], 1);
  EXPECT_EQ(json["rows"][1]["split_level"], 2);
  const auto totals_run = run_command(cachesim() + " run " + quoted(dir / "tree.din.zst") +
                                      " --size 128 --scheme split --format json");
  EXPECT_EQ(nlohmann::json::parse(totals_run.out)["rows"][0]["split_level"], 3);
}

// A DFL layout scatters the top levels: with 16-byte blocks (two nodes)
// levels 0-2 of a complete tree occupy 5 blocks, more than a 64-byte high
// cache holds though their 56 bytes fit; auto must pick K = 2, not abort.
TEST(SweepCommand, AutoSplitLevelOnDflWithLargerBlocksFits) {
  testing::TempDir dir;
  formats::WriterOptions options;
  options.form = formats::RecordForm::Din;
  auto writer = formats::TraceWriter::create(
      (dir / "dfl.din.zst").string(),
      {{"layout", {{"name", "dfl"}, {"node_size", 8}, {"node_base", 0}}}}, options);
  formats::AnimationFrameMarker marker;
  marker.nodes_per_level = {1, 2, 4, 8};
  writer->begin_animation_frame(marker);
  // Root-to-leaf paths in DFL slots.
  const std::vector<std::vector<std::uint64_t>> paths{
      {0, 1, 2, 3}, {0, 1, 2, 4}, {0, 1, 5, 6}, {0, 1, 5, 7},
      {0, 8, 9, 10}, {0, 8, 9, 11}, {0, 8, 12, 13}, {0, 8, 12, 14}};
  for (const auto& path : paths) {
    for (std::size_t level = 0; level < path.size(); ++level) {
      formats::Record record;
      record.address = path[level] * 8;
      record.tag = static_cast<formats::Tag>(level);
      writer->write(record);
    }
  }
  writer->finish();
  const auto result = run_command(cachesim() + " run " + quoted(dir / "dfl.din.zst") +
                                  " --size 128 --block 16 --scheme split --split-level auto "
                                  "--format csv");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(result.out.find(",split,128,16,1,lru,retain,64,64,2,32,32,"), std::string::npos)
      << result.out;
}

TEST(SweepCommand, BadSizeNamesTheOption) {
  for (const std::string option : {"--size", "--block", "--high-size", "--low-size"}) {
    const auto result = run_command(cachesim() + " run - --scheme split " + option + " 3x", "");
    EXPECT_EQ(result.exit_code, 2) << option;
    EXPECT_NE(result.err.find("cachesim run: " + option + ": '3x' is not a size"),
              std::string::npos)
        << result.err;
  }
}

TEST(SweepCommand, FitsErrorNamesTheSizes) {
  testing::TempDir dir;
  write_two_frame_container(dir / "tree.din.zst", 3);
  const auto result = run_command(cachesim() + " run " + quoted(dir / "tree.din.zst") +
                                  " --size 32 --scheme split --split-level 4");
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.err.find("16-byte high cache"), std::string::npos) << result.err;
  EXPECT_NE(result.err.find("do not fit"), std::string::npos) << result.err;
}

TEST(SweepCommand, UntaggedTraceForSplitSuggestsTagsAreLevels) {
  NODETRACE_SHARED_OR_SKIP(shared);
  const auto result =
      run_command(cachesim() + " run " + quoted(shared / "dinero-golden" / "kd-bfl-s1.din.zst") +
                  " --scheme split --split-level 6");
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.err.find("--tags-are-levels"), std::string::npos) << result.err;
}

TEST(SweepCommand, SeveralTracesInArgumentOrderAndStdin) {
  NODETRACE_SHARED_OR_SKIP(shared);
  const auto kd = shared / "dinero-golden" / "kd-bfl-s1.din.zst";
  const auto mm = shared / "dinero-golden" / "mm32.din.zst";
  const auto result = run_command(cachesim() + " run " + quoted(mm) + " - " + quoted(kd) +
                                      " --size 8k --format csv",
                                  testing::read_file(kd));
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const std::string expected_kd = ",single,8192,8,1,lru,,,,,200000,200000,39930,0.199650,,,,,\n";
  const auto mm_at = result.out.find(mm.string() + ",single");
  const auto stdin_at = result.out.find("\n-," + expected_kd.substr(1));
  const auto kd_at = result.out.find(kd.string() + expected_kd);
  EXPECT_NE(mm_at, std::string::npos) << result.out;
  EXPECT_NE(stdin_at, std::string::npos) << result.out;
  EXPECT_NE(kd_at, std::string::npos) << result.out;
  EXPECT_LT(mm_at, stdin_at);
  EXPECT_LT(stdin_at, kd_at);
}

TEST(SweepCommand, SingleEqualsCachesimDinero) {
  NODETRACE_SHARED_OR_SKIP(shared);
  struct Case {
    std::string trace;
    std::string informat;
    std::string size, block, assoc, policy;
  };
  const std::vector<Case> cases{
      {"mm32.din.zst", "d", "8192", "16", "4", "lru"},
      {"mm32.din.zst", "d", "1024", "16", "1", "lru"},
      {"mm32.din.zst", "d", "2048", "4", "1", "lru"},
      {"mm32.xdin.zst", "D", "16384", "64", "8", "fifo"},
      {"mm32.xdin.zst", "D", "1024", "4", "1", "lru"},
      {"kd-bfl-s1.din.zst", "d", "8192", "8", "4", "fifo"},
  };
  for (const Case& c : cases) {
    const auto trace = shared / "dinero-golden" / c.trace;
    const auto dinero = run_command(
        fmt::format("zstd -dc {} | {} dinero -informat {} -l1-usize {} -l1-ubsize {} "
                    "-l1-uassoc {} -l1-urepl {}",
                    quoted(trace), cachesim(), c.informat, c.size, c.block, c.assoc,
                    c.policy[0]));
    ASSERT_EQ(dinero.exit_code, 0) << dinero.err;
    const auto stats = wrap::parse_dinero_output(dinero.out);
    const auto run = run_command(fmt::format("{} run {} --size {} --block {} --assoc {} "
                                             "--policy {} --format csv",
                                             cachesim(), quoted(trace), c.size, c.block, c.assoc,
                                             c.policy));
    ASSERT_EQ(run.exit_code, 0) << run.err;
    const std::string expected =
        fmt::format(",{},{},", stats[0].demand_fetches, stats[0].demand_misses);
    EXPECT_NE(run.out.find(expected), std::string::npos)
        << c.trace << " " << c.size << ": " << run.out << " vs " << expected;
  }
}

TEST(SweepCommand, JsonAndPerLevelTables) {
  testing::TempDir dir;
  write_two_frame_container(dir / "tree.din.zst", 2);
  const auto result = run_command(cachesim() + " run " + quoted(dir / "tree.din.zst") +
                                  " --size 64 --scheme split --split-level 2 --per-level " +
                                  quoted(dir / "levels.json") + " --format json");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const auto json = nlohmann::json::parse(result.out);
  ASSERT_EQ(json.size(), 2u);  // columns, rows: the same keys with or without --per-level
  ASSERT_EQ(json["rows"].size(), 1u);
  EXPECT_EQ(json["rows"][0]["split_level"], 2);
  EXPECT_EQ(json["rows"][0]["high_loads"], 6);
  EXPECT_TRUE(json["rows"][0]["miss_ratio"].is_number());
  const auto levels = nlohmann::json::parse(testing::read_file(dir / "levels.json"));
  ASSERT_EQ(levels["rows"].size(), 5u);  // levels 0, 1, 2, 3, 5
  EXPECT_EQ(levels["rows"][0]["refs"], 400);
  EXPECT_EQ(levels["rows"][0]["misses"], 0);
  EXPECT_EQ(levels["rows"][0]["high_policy"], "retain");
  EXPECT_EQ(levels["rows"][0]["split_level"], 2);
  EXPECT_EQ(levels["rows"][4]["level"], 5);
  EXPECT_TRUE(result.err.empty()) << result.err;  // layout says 2: no note
}

TEST(SweepCommand, PerLevelAndPerFrameCannotBothTakeStandardOutput) {
  testing::TempDir dir;
  write_two_frame_container(dir / "tree.din.zst", 2);
  const auto result = run_command(cachesim() + " run " + quoted(dir / "tree.din.zst") +
                                  " --scheme split --per-level - --per-frame - --format csv");
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.err.find("one table per output"), std::string::npos) << result.err;
}

// Exit 2 with a message that names the option given; a missing trace is
// exit 1 naming the file.
TEST(SweepCommand, BadUsageExitsTwoNamingTheOption) {
  const auto bare = run_command(cachesim() + " run");
  EXPECT_EQ(bare.exit_code, 2);
  EXPECT_NE(bare.err.find("cachesim run: traces is required"), std::string::npos) << bare.err;
  const auto size = run_command(cachesim() + " run x --size 3k");
  EXPECT_EQ(size.exit_code, 2);
  EXPECT_NE(size.err.find("--size"), std::string::npos) << size.err;
  const auto policy = run_command(cachesim() + " run x --policy nope");
  EXPECT_EQ(policy.exit_code, 2);
  EXPECT_NE(policy.err.find("cachesim run: --policy: 'nope' is not one of"), std::string::npos) << policy.err;
  const auto missing = run_command(cachesim() + " run /nonexistent/t.din");
  EXPECT_EQ(missing.exit_code, 1);
  EXPECT_NE(missing.err.find("/nonexistent/t.din"), std::string::npos);
  EXPECT_EQ(run_command(cachesim() + " run --help").exit_code, 0);
}

}  // namespace
}  // namespace nodetrace::cachesim
