// Sweeps: single and split schemes on hand-made streams with answers worked
// out by hand, animation frames, K = auto, and the errors of docs/ARCHITECTURE.md.
#include <gtest/gtest.h>

#include "nodetrace/cachesim/sweep/sweep.hpp"
#include "nodetrace/base/error.hpp"

namespace nodetrace::cachesim {
namespace {

using formats::Record;
using formats::RecordBatch;

Record node(std::uint64_t address, formats::Tag level) {
  Record record;
  record.address = address;
  record.size = 8;
  record.tag = level;
  return record;
}

// One traversal: root (block 0), level-1 nodes (blocks 1, 2), level-2 nodes
// at 0x100 / 0x120 (blocks 32, 36). With 8-byte blocks:
//   single 32 B direct mapped (4 sets): 0 m, 1 m, 32 m, 0 m, 2 m, 36 m, 0 m, 1 h, 32 m = 8 misses
//   split K=2, low 16 B direct mapped (2 sets): 32 m, 36 m, 32 m = 3 misses;
//   high: distinct blocks 0, 1, 2 = 3 loads; as a 32 B direct-mapped cache: 0 m 1 m 0 h 2 m 0 h 1 h = 3
std::vector<Record> traversal() {
  return {node(0x0, 0),   node(0x8, 1),  node(0x100, 2), node(0x0, 0),  node(0x10, 1),
          node(0x120, 2), node(0x0, 0),  node(0x8, 1),   node(0x100, 2)};
}

TraceContext levels_context() {
  TraceContext context;
  context.trace = "t.din";
  context.source_name = "t.din";
  context.form = formats::RecordForm::ExtendedDin;
  context.tags_are_levels = true;
  return context;
}

Configuration single(std::uint64_t size) {
  Configuration config;
  config.size = size;
  config.block = 8;
  config.assoc = 1;
  return config;
}

Configuration split(HighPolicy policy, std::optional<std::uint32_t> level = 2) {
  Configuration config;
  config.scheme = Scheme::Split;
  config.high_size = 32;
  config.low_size = 16;
  config.size = 48;
  config.block = 8;
  config.assoc = 1;
  config.high_assoc = 1;
  config.high_policy = policy;
  config.split_level = level;
  return config;
}

RecordBatch batch_of(std::vector<Record> records, std::optional<std::uint64_t> frame = {},
                     std::vector<std::uint64_t> nodes_per_level = {}) {
  RecordBatch batch;
  batch.records = std::move(records);
  if (frame) {
    formats::AnimationFrameMarker marker;
    marker.frame = *frame;
    marker.nodes_per_level = std::move(nodes_per_level);
    batch.marker = marker;
  }
  return batch;
}

TraceResult run(std::vector<Configuration> configs, std::vector<RecordBatch> batches,
                TraceContext context = levels_context(), bool per_level = false) {
  Sweep sweep(std::move(configs), std::move(context), per_level);
  for (const auto& batch : batches) sweep.feed(batch);
  return sweep.finish();
}

TEST(Sweep, SingleAndSplitOnOneTraversal) {
  const TraceResult result =
      run({single(32), split(HighPolicy::Retain), split(HighPolicy::Cache)},
          {batch_of(traversal())});
  ASSERT_EQ(result.rows.size(), 3u);
  const ResultRow& one = result.rows[0];
  EXPECT_EQ(one.refs, 9u);
  EXPECT_EQ(one.fetches, 9u);
  EXPECT_EQ(one.misses, 8u);

  const ResultRow& retain = result.rows[1];
  EXPECT_EQ(retain.split_level, 2u);
  EXPECT_EQ(retain.high_refs, 6u);
  EXPECT_EQ(retain.low_refs, 3u);
  EXPECT_EQ(retain.high_misses, 0u);
  EXPECT_EQ(retain.high_loads, std::optional<std::uint64_t>(3));
  EXPECT_EQ(retain.low_misses, 3u);
  EXPECT_EQ(retain.misses, 3u);

  const ResultRow& cache = result.rows[2];
  EXPECT_EQ(cache.high_misses, 3u);
  EXPECT_EQ(cache.high_loads, std::nullopt);
  EXPECT_EQ(cache.low_misses, 3u);
  EXPECT_EQ(cache.misses, 6u);
}

TEST(Sweep, CountLoadsMakesLoadsMisses) {
  Configuration config = split(HighPolicy::Retain);
  config.count_loads = true;
  const TraceResult result = run({config}, {batch_of(traversal())});
  EXPECT_EQ(result.rows[0].high_misses, 3u);
  EXPECT_EQ(result.rows[0].misses, 6u);
}

TEST(Sweep, RetainReloadsEachAnimationFrameAndLowCacheIsKept) {
  const TraceResult result = run({split(HighPolicy::Retain), split(HighPolicy::Cache)},
                                 {batch_of(traversal(), 0), batch_of(traversal(), 1)});
  const ResultRow& retain = result.rows[0];
  EXPECT_EQ(retain.high_loads, std::optional<std::uint64_t>(6));  // 3 per frame
  EXPECT_EQ(retain.high_misses, 0u);
  // Frame 1's low cache still holds block 32 (set 0): 32 h, 36 m, 32 m.
  EXPECT_EQ(retain.low_misses, 3u + 2u);
  // An ordinary high cache is not reloaded: frame 1 finds blocks 0, 1, 2 resident.
  const ResultRow& cache = result.rows[1];
  EXPECT_EQ(cache.high_misses, 3u);
}

TEST(Sweep, TraceWithoutMarkersIsOneAnimationFrame) {
  const TraceResult result = run({split(HighPolicy::Retain)},
                                 {batch_of(traversal()), batch_of(traversal())});
  EXPECT_EQ(result.rows[0].high_loads, std::optional<std::uint64_t>(3));
}

TEST(Sweep, HighLevelsThatDoNotFitAreAnErrorNamingTheSizes) {
  Configuration config = split(HighPolicy::Retain);
  config.high_size = 16;  // 2 blocks, 3 needed
  config.size = 32;
  try {
    run({config}, {batch_of(traversal(), 4)});
    FAIL() << "expected an error";
  } catch (const base::UsageError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("16-byte high cache"), std::string::npos) << message;
    EXPECT_NE(message.find("animation frame 4"), std::string::npos) << message;
    EXPECT_NE(message.find("record 5"), std::string::npos) << message;
    EXPECT_NE(message.find("--high-size"), std::string::npos) << message;
  }
}

TEST(Sweep, AutoSplitLevelFromMarkers) {
  // The shared K-sizing, counting bytes of contiguous levels.
  auto auto_split_level = [](std::vector<std::uint64_t> nodes_per_level, std::uint64_t node_size,
                             std::uint64_t high_size) {
    base::LevelPlacement placement;
    placement.node_size = node_size;
    return base::split_level_for_capacity(nodes_per_level, placement, high_size);
  };
  EXPECT_EQ(auto_split_level({1, 2, 4, 8}, 8, 32), 2u);   // 8 + 16 = 24 <= 32 < 56
  EXPECT_EQ(auto_split_level({1, 2, 4, 8}, 8, 56), 3u);
  EXPECT_EQ(auto_split_level({1, 2, 4, 8}, 8, 4096), 4u);
  EXPECT_EQ(auto_split_level({1, 2}, 8, 4), 0u);

  TraceContext context = levels_context();
  context.layout.split_level = 3;
  const TraceResult result = run({split(HighPolicy::Retain, std::nullopt)},
                                 {batch_of(traversal(), 0, {1, 2, 4, 8})}, context);
  EXPECT_EQ(result.rows[0].split_level, 2u);
  ASSERT_EQ(result.notes.size(), 1u);
  EXPECT_NE(result.notes[0].find("split level 2 (auto) differs from the layout's split_level 3"),
            std::string::npos)
      << result.notes[0];
}

// Frame 0's tree {1, 2, 4, 8}: levels 0, 1 fit 32 bytes, K = 2. Frame 1's
// tree {1, 4, ...}: level 1 alone is 32 bytes, K = 1, so its level-1 records
// go to the low cache.
TEST(Sweep, AutoSplitLevelIsResolvedPerAnimationFrame) {
  Sweep sweep({split(HighPolicy::Retain, std::nullopt)}, levels_context(), false, true);
  sweep.feed(batch_of(traversal(), 0, {1, 2, 4, 8}));
  sweep.feed(batch_of(traversal(), 1, {1, 4, 4, 8}));
  const TraceResult result = sweep.finish();
  ASSERT_EQ(result.animation_frame_rows.size(), 2u);
  const ResultRow& first = result.animation_frame_rows[0].row;
  const ResultRow& second = result.animation_frame_rows[1].row;
  EXPECT_EQ(result.animation_frame_rows[0].frame, 0u);
  EXPECT_EQ(result.animation_frame_rows[1].frame, 1u);
  EXPECT_EQ(first.split_level, 2u);
  EXPECT_EQ(first.high_refs, 6u);
  EXPECT_EQ(first.low_refs, 3u);
  EXPECT_EQ(first.high_loads, std::optional<std::uint64_t>(3));
  EXPECT_EQ(first.low_misses, 3u);  // 32 m, 36 m, 32 m
  EXPECT_EQ(second.split_level, 1u);
  EXPECT_EQ(second.high_refs, 3u);
  EXPECT_EQ(second.low_refs, 6u);
  EXPECT_EQ(second.high_loads, std::optional<std::uint64_t>(1));
  // Low cache (2 sets) kept from frame 0 with block 32 in set 0:
  // 1 m, 32 h, 2 m, 36 m, 1 h, 32 m.
  EXPECT_EQ(second.low_misses, 4u);
  // The totals row: the sums, and the first frame's K.
  const ResultRow& total = result.rows.at(0);
  EXPECT_EQ(total.split_level, 2u);
  EXPECT_EQ(total.high_refs, 9u);
  EXPECT_EQ(total.low_refs, 9u);
  EXPECT_EQ(total.high_loads, std::optional<std::uint64_t>(4));
  EXPECT_EQ(total.low_misses, 7u);
  EXPECT_EQ(total.misses, 7u);
  bool noted = false;
  for (const std::string& note : result.notes) {
    noted = noted || note.find("split level (auto) from 1 to 2 over 2 animation frames") !=
                         std::string::npos;
  }
  EXPECT_TRUE(noted);
}

// DFL slots of a complete 4-level tree: level 0 slot 0, level 1 slots 1 and
// 8, level 2 slots 2, 5, 9, 12. With 16-byte blocks (two 8-byte nodes) levels
// 0-2 occupy the blocks of slots {0,1}, {2}, {4,5}, {8,9}, {12}: 5 blocks, more
// than a 64-byte high cache's 4, though their 56 bytes are fewer than 64.
TEST(Sweep, AutoSplitLevelCountsTheBlocksOfScatteredLevels) {
  TraceContext context = levels_context();
  context.layout.name = "dfl";
  Configuration config = split(HighPolicy::Retain, std::nullopt);
  config.block = 16;
  config.high_size = 64;
  config.low_size = 64;
  config.size = 128;
  const std::vector<std::vector<std::uint64_t>> paths{{0, 1, 2}, {0, 1, 5}, {0, 8, 9}, {0, 8, 12}};
  std::vector<Record> records;
  for (const auto& path : paths) {
    for (std::size_t level = 0; level < path.size(); ++level) {
      records.push_back(node(path[level] * 8, static_cast<formats::Tag>(level)));
    }
  }
  const TraceResult result = run({config}, {batch_of(records, 0, {1, 2, 4, 8})}, context);
  // Levels 0, 1 occupy at most 3 blocks (one per node): K = 2, and they fit.
  EXPECT_EQ(result.rows.at(0).split_level, 2u);
  EXPECT_EQ(result.rows.at(0).high_loads, std::optional<std::uint64_t>(2));
  // The BFL layout keeps levels 0-2 in slots 0-6: 4 blocks, K = 3.
  context.layout.name = "bfl";
  formats::AnimationFrameMarker marker;
  marker.nodes_per_level = {1, 2, 4, 8};
  EXPECT_EQ(simulated_split_level(config, &marker, context), 3u);
}

TEST(Sweep, AutoSplitLevelWithoutMarkersAsksForK) {
  try {
    run({split(HighPolicy::Retain, std::nullopt)}, {batch_of(traversal())});
    FAIL() << "expected an error";
  } catch (const base::UsageError& error) {
    EXPECT_NE(std::string(error.what()).find("give an explicit split level"), std::string::npos)
        << error.what();
  }
}

TEST(Sweep, UntaggedTraceIsAnErrorForSplitThatSuggestsTagsAreLevels) {
  TraceContext context = levels_context();
  context.tags_are_levels = false;
  try {
    Sweep sweep({split(HighPolicy::Retain)}, context, false);
    FAIL() << "expected an error";
  } catch (const base::UsageError& error) {
    EXPECT_NE(std::string(error.what()).find("--tags-are-levels"), std::string::npos)
        << error.what();
  }
  // The single scheme simulates untagged records.
  std::vector<Record> records = traversal();
  for (Record& record : records) record.tag = formats::kTagNone;
  const TraceResult result = run({single(32)}, {batch_of(records)}, context);
  EXPECT_EQ(result.rows[0].misses, 8u);
}

TEST(Sweep, UntaggedRecordInALevelTaggedTraceNamesTheRecord) {
  std::vector<Record> records = traversal();
  records[6].tag = formats::kTagNone;
  RecordBatch batch = batch_of(records);
  batch.first_record = 100;
  try {
    run({split(HighPolicy::Retain)}, {batch});
    FAIL() << "expected an error";
  } catch (const base::FormatError& error) {
    EXPECT_NE(std::string(error.what()).find("t.din: record 107"), std::string::npos)
        << error.what();
  }
}

TEST(Sweep, OtherStreamRecordsAreCountedApartNotSimulated) {
  std::vector<Record> records = traversal();
  records.insert(records.begin() + 1, node(0x100, formats::kTagPrimitiveList));
  records.insert(records.begin() + 4, node(0x8000, formats::kTagTriangle));
  const TraceResult result =
      run({single(32), split(HighPolicy::Retain)}, {batch_of(records)});
  EXPECT_EQ(result.other_stream_records, 2u);
  EXPECT_EQ(result.rows[0].refs, 9u);
  EXPECT_EQ(result.rows[0].misses, 8u);
  EXPECT_EQ(result.rows[1].refs, 9u);
  EXPECT_EQ(result.rows[1].misses, 3u);
  ASSERT_EQ(result.notes.size(), 1u);
  EXPECT_NE(result.notes[0].find("2 records tagged p or t"), std::string::npos);
}

TEST(Sweep, PerLevelCounts) {
  const TraceResult result =
      run({single(32), split(HighPolicy::Retain)}, {batch_of(traversal())}, levels_context(), true);
  // single: level 0: 0 m, 0 m, 0 m = 3; level 1: 1 m, 2 m, 1 h = 2; level 2: 32 m, 36 m, 32 m = 3
  // split (retain): levels 0, 1 never miss; level 2 misses 3.
  ASSERT_EQ(result.level_rows.size(), 6u);
  const std::vector<std::uint64_t> misses{3, 2, 3, 0, 0, 3};
  for (std::size_t i = 0; i < 6; ++i) {
    EXPECT_EQ(result.level_rows[i].level, i % 3);
    EXPECT_EQ(result.level_rows[i].refs, 3u);
    EXPECT_EQ(result.level_rows[i].misses, misses[i]) << i;
    EXPECT_EQ(result.level_rows[i].config.scheme, i < 3 ? Scheme::Single : Scheme::Split);
  }
}

TEST(Sweep, ReferenceSpanningTwoBlocksIsTwoFetches) {
  // xdin keeps size: 8 bytes at 4 span blocks 0 and 1.
  std::vector<Record> records{node(0x4, 0), node(0x8, 0)};
  const TraceResult xdin = run({single(32)}, {batch_of(records)});
  EXPECT_EQ(xdin.rows[0].refs, 2u);
  EXPECT_EQ(xdin.rows[0].fetches, 3u);
  EXPECT_EQ(xdin.rows[0].misses, 2u);
  // din gives every record 4 bytes at a multiple of 4: one block each.
  TraceContext din = levels_context();
  din.form = formats::RecordForm::Din;
  records[0].address = 0x6;  // simulated as 4
  const TraceResult din_result = run({single(32)}, {batch_of(records)}, din);
  EXPECT_EQ(din_result.rows[0].fetches, 2u);
  EXPECT_EQ(din_result.rows[0].misses, 2u);
}

TEST(Sweep, CopyBackAndInvalidateAreNotDemandFetches) {
  std::vector<Record> records{node(0x0, 0), node(0x0, 0), node(0x0, 0), node(0x0, 0)};
  records[1].type = formats::AccessType::CopyBack;
  records[2].type = formats::AccessType::Invalidate;
  const TraceResult result = run({single(32)}, {batch_of(records)});
  EXPECT_EQ(result.rows[0].refs, 4u);
  EXPECT_EQ(result.rows[0].fetches, 2u);
  EXPECT_EQ(result.rows[0].misses, 2u);  // invalidated, so the last one misses
}

TEST(Sweep, PartsForThreadsGiveTheSameResults) {
  const std::vector<Configuration> configs{single(32), split(HighPolicy::Retain),
                                             split(HighPolicy::Cache), single(64)};
  std::vector<RecordBatch> batches{batch_of(traversal(), 0), batch_of(traversal(), 1)};
  const TraceResult together = run(configs, batches);
  Sweep sweep(configs, levels_context(), false);
  sweep.set_parts(3);
  for (const auto& batch : batches) {
    sweep.begin_batch(batch);
    EXPECT_EQ(sweep.part_count(), 3u);
    for (std::size_t part = 3; part-- > 0;) sweep.feed_part(batch, part);
  }
  const TraceResult parted = sweep.finish();
  ASSERT_EQ(parted.rows.size(), together.rows.size());
  for (std::size_t i = 0; i < parted.rows.size(); ++i) {
    EXPECT_EQ(parted.rows[i].config.size, together.rows[i].config.size);
    EXPECT_EQ(parted.rows[i].misses, together.rows[i].misses) << i;
    EXPECT_EQ(parted.rows[i].high_loads, together.rows[i].high_loads) << i;
  }
}

TEST(Sweep, ConfigurationsSimulatedTogetherEqualEachAlone) {
  // Sizes of one kind share one loop (grouped); each alone has its own.
  std::vector<Configuration> configs;
  for (const std::uint64_t size : {16u, 32u, 64u, 128u}) configs.push_back(single(size));
  for (const std::uint64_t low : {16u, 32u, 64u}) {
    Configuration config = split(HighPolicy::Retain);
    config.high_size = 128;  // 9 high blocks touched per frame
    config.low_size = low;
    config.size = config.high_size + low;
    config.count_loads = low == 32;
    configs.push_back(config);
  }
  std::vector<Record> records;
  for (int repeat = 0; repeat < 5; ++repeat) {
    for (Record record : traversal()) {
      record.address += static_cast<std::uint64_t>(repeat % 3) * 0x40;
      records.push_back(record);
    }
  }
  const std::vector<RecordBatch> batches{batch_of(records, 0), batch_of(records, 1)};
  const TraceResult together = run(configs, batches);
  for (std::size_t i = 0; i < configs.size(); ++i) {
    const TraceResult alone = run({configs[i]}, batches);
    EXPECT_EQ(together.rows[i].misses, alone.rows[0].misses) << i;
    EXPECT_EQ(together.rows[i].low_misses, alone.rows[0].low_misses) << i;
    EXPECT_EQ(together.rows[i].high_misses, alone.rows[0].high_misses) << i;
    EXPECT_EQ(together.rows[i].high_loads, alone.rows[0].high_loads) << i;
    EXPECT_EQ(together.rows[i].high_refs, alone.rows[0].high_refs) << i;
  }
  EXPECT_EQ(together.rows[5].high_misses, *together.rows[5].high_loads);  // --count-loads
}

TEST(Sweep, ExpandsEveryCombinationInReportOrder) {
  SweepOptions options;
  options.sizes = {4096, 8192, 16384};
  options.schemes = {Scheme::Single, Scheme::Split};
  options.split_levels = {std::nullopt};
  const auto configs = expand_configurations(options);
  ASSERT_EQ(configs.size(), 6u);
  EXPECT_EQ(configs[0].size, 4096u);
  EXPECT_EQ(configs[0].scheme, Scheme::Single);
  EXPECT_EQ(configs[1].scheme, Scheme::Split);
  EXPECT_EQ(configs[1].high_size, 2048u);
  EXPECT_EQ(configs[1].low_size, 2048u);
  EXPECT_EQ(configs[5].size, 16384u);

  options.sizes = {8192};
  options.assocs = {0};
  options.high_size = 2048;
  // The rest, 6144 bytes, is not a power of two.
  EXPECT_THROW(expand_configurations(options), base::UsageError);
  options.low_size = 4096;
  const auto full = expand_configurations(options);
  EXPECT_EQ(full[0].assoc, 1024u);
  EXPECT_EQ(full[1].size, 6144u);  // total = high + low
  EXPECT_EQ(full[1].high_size, 2048u);
  EXPECT_EQ(full[1].low_size, 4096u);
  EXPECT_EQ(full[1].assoc, 512u);
  EXPECT_EQ(full[1].high_assoc, 256u);
}

TEST(Sweep, ParsesAssociativities) {
  EXPECT_EQ(parse_assoc("full"), 0u);
  EXPECT_EQ(parse_assoc("4"), 4u);
  EXPECT_THROW(parse_assoc("0"), base::UsageError);
}

}  // namespace
}  // namespace nodetrace::cachesim
