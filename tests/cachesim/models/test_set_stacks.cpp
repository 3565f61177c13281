// The stack path (set stacks answering many configurations in one pass)
// against the per-configuration path (each configuration simulated alone)
// and against the node cache: every count of ResultRow, the --per-level and
// --per-frame rows, on random streams and on a rendered trace; and a sweep
// split into parts for threads (stack groups cut into pieces) against one
// part.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <bit>
#include <random>

#include "nodetrace/cachesim/models/set_associative_cache.hpp"
#include "nodetrace/cachesim/models/set_stacks.hpp"
#include "nodetrace/cachesim/sweep/sweep.hpp"
#include "nodetrace/base/error.hpp"
#include "nodetrace/formats/read/trace_reader.hpp"
#include "test_support.hpp"

namespace nodetrace::cachesim {
namespace {

using formats::AccessType;
using formats::Record;
using formats::RecordBatch;

// Blocks with locality: mostly near the previous one, sometimes anywhere.
std::vector<std::uint64_t> random_blocks(std::size_t count, std::uint64_t seed) {
  std::mt19937_64 random(seed);
  std::vector<std::uint64_t> blocks;
  std::uint64_t at = 0;
  for (std::size_t i = 0; i < count; ++i) {
    at = random() % 6 == 0 ? random() % 8192 : (at + random() % 9) % 8192;
    blocks.push_back(at);
  }
  return blocks;
}

// access_blocks() of `blocks` in batches of uneven length (up to
// `longest`), as a sweep's batches end anywhere.
void access_in_uneven_batches(SetStacks& stacks, const std::vector<std::uint64_t>& blocks,
                              std::size_t longest) {
  for (std::size_t begin = 0; begin < blocks.size();) {
    const std::size_t count = std::min<std::size_t>(1 + begin % longest, blocks.size() - begin);
    stacks.access_blocks(blocks.data() + begin, count);
    begin += count;
  }
}

TEST(SetStacks, EverySetCountAndWaysEqualsAnLruNodeCache) {
  // Set counts 1..256 with stacks 1..16 deep (not all powers of two).
  const std::vector<SetStacks::Level> levels{{0, 16}, {2, 8}, {3, 3}, {5, 1}, {6, 4}, {8, 2}};
  for (const std::uint64_t seed : {1u, 2u}) {
    const auto blocks = random_blocks(40000, seed);
    SetStacks stacks(levels);
    for (const std::uint64_t block : blocks) stacks.access(block);
    EXPECT_EQ(stacks.fetches(), blocks.size());
    for (const SetStacks::Level& level : levels) {
      for (std::uint32_t ways = 1; ways <= level.depth; ++ways) {
        const std::uint64_t sets = std::uint64_t{1} << level.log2_sets;
        if (!std::has_single_bit(ways)) continue;
        SetAssociativeCache cache({sets * ways * 8, 8, ways, ReplacementPolicy::Lru});
        std::uint64_t misses = 0;
        for (const std::uint64_t block : blocks) misses += cache.access(block);
        EXPECT_EQ(stacks.misses(level.log2_sets, ways), misses)
            << "seed " << seed << ", " << sets << " sets, " << ways << " ways";
      }
    }
  }
}

TEST(SetStacks, WaysOfAreTheCacheContents) {
  const auto blocks = random_blocks(5000, 3);
  SetStacks stacks({{2, 4}});
  SetAssociativeCache cache({4 * 2 * 8, 8, 2, ReplacementPolicy::Lru});
  for (const std::uint64_t block : blocks) {
    stacks.access(block);
    cache.access(block);
  }
  // A copy filled from the stacks behaves as the cache from here on.
  SetAssociativeCache copy({4 * 2 * 8, 8, 2, ReplacementPolicy::Lru});
  for (std::uint64_t set = 0; set < 4; ++set) copy.assign_set(set, stacks.ways_of(2, set, 2));
  for (const std::uint64_t block : random_blocks(5000, 4)) {
    EXPECT_EQ(copy.access(block), cache.access(block)) << block;
  }
}

// access_records() of records of 8-byte blocks whose addresses give
// `blocks` (anywhere in the block), in batches of uneven length.
void access_records_in_uneven_batches(SetStacks& stacks, const std::vector<std::uint64_t>& blocks,
                                      std::size_t longest) {
  std::vector<Record> records;
  for (std::size_t i = 0; i < blocks.size(); ++i) records.push_back({.address = (blocks[i] << 3) + i % 8});
  for (std::size_t begin = 0; begin < records.size();) {
    const std::size_t count = std::min<std::size_t>(1 + begin % longest, records.size() - begin);
    stacks.access_records(records.data() + begin, count, 3);
    begin += count;
  }
}

TEST(SetStacks, BlocksSetCountBySetCountEqualTheWalk) {
  // Every depth with a vector path (1, 2, 4, 8, 16) and others (3, 32).
  const std::vector<SetStacks::Level> levels{{0, 32}, {1, 16}, {2, 8}, {3, 3}, {4, 4}, {5, 2}, {6, 1}, {8, 1}};
  for (const std::uint64_t seed : {5u, 6u}) {
    const auto blocks = random_blocks(30000, seed);
    SetStacks walked(levels);
    SetStacks by_set_count(levels);
    SetStacks from_records(levels);  // the first set count a wide one
    for (const std::uint64_t block : blocks) walked.access(block);
    access_in_uneven_batches(by_set_count, blocks, 4099);
    access_records_in_uneven_batches(from_records, blocks, 4099);
    EXPECT_EQ(by_set_count.fetches(), walked.fetches());
    EXPECT_EQ(from_records.fetches(), walked.fetches());
    for (const SetStacks::Level& level : levels) {
      for (std::uint32_t ways = 1; ways <= level.depth; ++ways) {
        EXPECT_EQ(by_set_count.misses(level.log2_sets, ways), walked.misses(level.log2_sets, ways))
            << "seed " << seed << ", 2^" << level.log2_sets << " sets, " << ways << " ways";
        EXPECT_EQ(from_records.misses(level.log2_sets, ways), walked.misses(level.log2_sets, ways))
            << "records, seed " << seed << ", 2^" << level.log2_sets << " sets, " << ways << " ways";
      }
      const std::uint64_t sets = std::uint64_t{1} << level.log2_sets;
      for (std::uint64_t set = 0; set < sets; ++set) {
        EXPECT_EQ(by_set_count.ways_of(level.log2_sets, set, level.depth),
                  walked.ways_of(level.log2_sets, set, level.depth));
      }
      EXPECT_EQ(by_set_count.walk(level.log2_sets).visits, walked.walk(level.log2_sets).visits);
      EXPECT_EQ(by_set_count.walk(level.log2_sets).places, walked.walk(level.log2_sets).places);
    }
  }
}

// Stacks start with 32-bit blocks and widen to 64-bit ones before the first
// block that needs more (set_stacks.hpp). Blocks that agree in their low
// 32 bits (b and b + 2^32, in the same set of every set count) and the
// block 2^32 - 1 (the narrow stacks' free place) come after the widening,
// so a truncating or early narrow path miscounts them; every way of feeding
// (one block, a batch of blocks, a batch of records) against LRU caches,
// and the contents after.
TEST(SetStacks, WideningPartwayKeepsEveryCountExact) {
  const std::vector<SetStacks::Level> levels{{0, 8}, {2, 8}, {3, 4}, {4, 2}, {5, 1}, {6, 16}, {7, 3}};
  constexpr std::uint64_t kHigh = std::uint64_t{1} << 32;
  for (const std::uint64_t seed : {7u, 8u}) {
    const auto low = random_blocks(20000, seed);
    std::vector<std::uint64_t> blocks(low.begin(), low.begin() + 9000);
    // Narrow until here, then: the last narrow-fitting block's neighbour
    // (2^32 - 1) and aliases of blocks still held, mixed with the old ones.
    blocks.push_back(kHigh - 1);
    for (std::size_t i = 9000; i < low.size(); ++i) {
      const std::uint64_t alias = i % 3 == 0 ? kHigh : i % 3 == 1 ? 0 : kHigh * 5;
      blocks.push_back(low[i] % 64 + alias);
      blocks.push_back(i % 7 == 0 ? kHigh - 1 : low[i]);
    }
    SetStacks walked(levels);
    SetStacks batched(levels);
    SetStacks from_records(levels);
    for (const std::uint64_t block : blocks) walked.access(block);
    // The widening falls inside one of the batches.
    access_in_uneven_batches(batched, blocks, 3001);
    access_records_in_uneven_batches(from_records, blocks, 3001);
    for (const SetStacks::Level& level : levels) {
      const std::uint64_t sets = std::uint64_t{1} << level.log2_sets;
      for (std::uint32_t ways = 1; ways <= level.depth; ways *= 2) {
        SetAssociativeCache cache({sets * ways * 8, 8, ways, ReplacementPolicy::Lru});
        std::uint64_t misses = 0;
        for (const std::uint64_t block : blocks) misses += cache.access(block);
        const std::string what = fmt::format("seed {}, {} sets, {} ways", seed, sets, ways);
        EXPECT_EQ(walked.misses(level.log2_sets, ways), misses) << what;
        EXPECT_EQ(batched.misses(level.log2_sets, ways), misses) << what;
        EXPECT_EQ(from_records.misses(level.log2_sets, ways), misses) << what;
      }
      for (std::uint64_t set = 0; set < sets; ++set) {
        EXPECT_EQ(batched.ways_of(level.log2_sets, set, level.depth),
                  walked.ways_of(level.log2_sets, set, level.depth));
        EXPECT_EQ(from_records.ways_of(level.log2_sets, set, level.depth),
                  walked.ways_of(level.log2_sets, set, level.depth));
      }
    }
    // The contents after widening are the 64-bit blocks themselves.
    SetAssociativeCache cache({4 * 2 * 8, 8, 2, ReplacementPolicy::Lru});
    for (const std::uint64_t block : blocks) cache.access(block);
    SetAssociativeCache copy({4 * 2 * 8, 8, 2, ReplacementPolicy::Lru});
    for (std::uint64_t set = 0; set < 4; ++set) copy.assign_set(set, batched.ways_of(2, set, 2));
    for (const std::uint64_t block : {kHigh - 1, kHigh + 1, std::uint64_t{1}, kHigh * 5 + 2}) {
      EXPECT_EQ(copy.access(block), cache.access(block)) << block;
    }
  }
}

// Narrow stacks hold contents as the wide ones do: free places are
// SetStacks::kEmpty, and a block equal to 2^32 - 2 (the largest narrow
// one) is kept as itself.
TEST(SetStacks, NarrowContentsAreTheBlocksAndFreePlacesAreEmpty) {
  SetStacks stacks({{1, 4}});
  const std::uint64_t largest = (std::uint64_t{1} << 32) - 2;
  stacks.access(largest);
  stacks.access(4);
  EXPECT_EQ(stacks.ways_of(1, 0, 4),
            (std::vector<std::uint64_t>{4, largest, SetStacks::kEmpty, SetStacks::kEmpty}));
  EXPECT_EQ(stacks.ways_of(1, 1, 4), std::vector<std::uint64_t>(4, SetStacks::kEmpty));
}

TraceContext context_of(formats::RecordForm form) {
  TraceContext context;
  context.trace = "t";
  context.source_name = "t";
  context.form = form;
  context.tags_are_levels = true;
  return context;
}

// Node fetches with levels 0..19; `mixed` adds odd sizes (spans), every
// access type and records of the other streams; `invalidates` adds
// invalidate records after the first third (the stacks hand over there).
std::vector<Record> random_records(std::uint64_t seed, std::size_t count, bool mixed,
                                   bool invalidates) {
  std::mt19937_64 random(seed);
  std::vector<Record> records(count);
  std::uint64_t at = 0;
  for (std::size_t i = 0; i < count; ++i) {
    Record& record = records[i];
    at = random() % 8 == 0 ? random() % 16384 : (at + random() % 5) % 16384;
    record.address = at * 8 + (mixed ? random() % 8 : 0);
    record.size = mixed ? 1 + static_cast<std::uint32_t>(random() % 16) : 8;
    // Levels < K <= 12 hold few blocks (2^(K-1)), so the high caches fit
    // every K that auto gives for them.
    record.tag = static_cast<formats::Tag>(at < 2048 ? std::bit_width(at) : 12 + at % 8);
    if (mixed) {
      const auto draw = random() % 40;
      record.type = draw < 30   ? AccessType::Read
                    : draw < 35 ? AccessType::Write
                    : draw < 37 ? AccessType::InstructionFetch
                    : draw < 38 ? AccessType::Misc
                                : AccessType::CopyBack;
      if (random() % 50 == 0) record.tag = formats::kTagTriangle;
    }
    if (invalidates && i > count / 3 && random() % 100 == 0) record.type = AccessType::Invalidate;
  }
  return records;
}

// Batches of 3000 records; every second one starts an animation frame
// (`marker_of` the frame's number gives its marker).
template <typename MarkerOf>
std::vector<RecordBatch> batches_of(const std::vector<Record>& records, MarkerOf marker_of) {
  std::vector<RecordBatch> batches;
  for (std::size_t begin = 0; begin < records.size(); begin += 3000) {
    RecordBatch batch;
    batch.first_record = begin;
    batch.records.assign(records.begin() + static_cast<std::ptrdiff_t>(begin),
                         records.begin() + static_cast<std::ptrdiff_t>(
                                               std::min(records.size(), begin + 3000)));
    if (begin % 6000 == 0) batch.marker = marker_of(begin / 6000);
    batches.push_back(std::move(batch));
  }
  return batches;
}

// Markers whose nodes_per_level make K = auto change between frames.
std::vector<RecordBatch> batches_of(const std::vector<Record>& records) {
  return batches_of(records, [](std::uint64_t frame) {
    formats::AnimationFrameMarker marker;
    marker.frame = frame;
    const std::uint64_t wide = 1 + frame % 3;
    for (std::uint64_t level = 0; level < 20; ++level) {
      marker.nodes_per_level.push_back(std::min<std::uint64_t>(wide << level, 4000));
    }
    return marker;
  });
}

TraceResult sweep_of(const std::vector<Configuration>& configs,
                     const std::vector<RecordBatch>& batches, formats::RecordForm form,
                     bool per_level, bool per_animation_frame) {
  Sweep sweep(configs, context_of(form), per_level, per_animation_frame);
  for (const RecordBatch& batch : batches) sweep.feed(batch);
  return sweep.finish();
}

void expect_rows_equal(const ResultRow& together, const ResultRow& alone, const std::string& what) {
  EXPECT_EQ(together.split_level, alone.split_level) << what;
  EXPECT_EQ(together.refs, alone.refs) << what;
  EXPECT_EQ(together.fetches, alone.fetches) << what;
  EXPECT_EQ(together.misses, alone.misses) << what;
  EXPECT_EQ(together.high_refs, alone.high_refs) << what;
  EXPECT_EQ(together.high_misses, alone.high_misses) << what;
  EXPECT_EQ(together.high_loads, alone.high_loads) << what;
  EXPECT_EQ(together.low_refs, alone.low_refs) << what;
  EXPECT_EQ(together.low_misses, alone.low_misses) << what;
}

// Every configuration of the sweep together (stack groups) against each
// simulated alone (one configuration: the per-configuration path).
void expect_together_equals_alone(const std::vector<Configuration>& configs,
                                  const std::vector<RecordBatch>& batches,
                                  formats::RecordForm form, bool per_level) {
  const TraceResult together = sweep_of(configs, batches, form, per_level, true);
  ASSERT_EQ(together.rows.size(), configs.size());
  const std::size_t frames = together.animation_frame_rows.size() / configs.size();
  EXPECT_GT(frames, 1u);
  std::size_t level_row = 0;
  for (std::size_t i = 0; i < configs.size(); ++i) {
    const TraceResult alone = sweep_of({configs[i]}, batches, form, per_level, true);
    const Configuration& config = configs[i];
    const std::string what = fmt::format(
        "config {}: {} size {} assoc {} policy {} high {} {} K {}", i,
        scheme_name(config.scheme), config.size, config.assoc, policy_name(config.policy),
        high_policy_name(config.high_policy), config.high_size,
        config.split_level ? std::to_string(*config.split_level) : "auto");
    expect_rows_equal(together.rows[i], alone.rows[0], what);
    ASSERT_EQ(alone.animation_frame_rows.size(), frames) << what;
    for (std::size_t f = 0; f < frames; ++f) {
      const AnimationFrameRow& row = together.animation_frame_rows[f * configs.size() + i];
      EXPECT_EQ(row.frame, alone.animation_frame_rows[f].frame) << what;
      expect_rows_equal(row.row, alone.animation_frame_rows[f].row, what + fmt::format(" frame {}", f));
    }
    for (const LevelRow& alone_row : alone.level_rows) {
      ASSERT_LT(level_row, together.level_rows.size()) << what;
      const LevelRow& row = together.level_rows[level_row++];
      EXPECT_EQ(row.level, alone_row.level) << what;
      EXPECT_EQ(row.refs, alone_row.refs) << what << " level " << row.level;
      EXPECT_EQ(row.misses, alone_row.misses) << what << " level " << row.level;
    }
  }
  EXPECT_EQ(level_row, together.level_rows.size());
  EXPECT_EQ(together.other_stream_records, sweep_of({configs[0]}, batches, form, false, false)
                                               .other_stream_records);
}

Configuration split_config(std::uint32_t block, std::uint64_t high_size, std::uint64_t low_size,
                             std::uint32_t assoc, std::uint32_t split_level) {
  Configuration config;
  config.scheme = Scheme::Split;
  config.block = block;
  config.high_size = high_size;
  config.low_size = low_size;
  config.size = high_size + low_size;
  config.assoc = assoc;
  config.split_level = split_level;
  return config;
}

// Sizes x ways x policies, single and split (retain with given and auto K,
// cache), so several stack groups and per-configuration simulators mix.
std::vector<Configuration> design_space(std::uint32_t block) {
  SweepOptions options;
  options.sizes = {1024, 2048, 4096, 16384};
  options.blocks = {block};
  options.assocs = {1, 2, 4, 8};
  options.policies = {ReplacementPolicy::Lru, ReplacementPolicy::Fifo};
  options.schemes = {Scheme::Single, Scheme::Split};
  options.split_levels = {std::nullopt, 6};
  options.high_policies = {HighPolicy::Retain, HighPolicy::Cache};
  std::vector<Configuration> configs = expand_configurations(options);
  // Split configurations of several totals with one high cache: the low
  // caches of one K are one question across totals too.
  for (const std::uint64_t low : {512u, 1024u, 4096u}) {
    Configuration config = split_config(block, 8192, low, 2, 6);
    config.count_loads = low == 1024;
    configs.push_back(config);
  }
  return configs;
}

// Table 1's shape: direct mapped, one policy, K = auto for each size (so
// every split configuration has a K of its own and they are fed together by
// one loop), and split `cache` ones with three given K.
std::vector<Configuration> table1_grid(std::uint32_t block) {
  SweepOptions options;
  options.sizes = {1024, 2048, 4096, 16384};
  options.blocks = {block};
  options.schemes = {Scheme::Single, Scheme::Split};
  std::vector<Configuration> configs = expand_configurations(options);
  for (const std::uint32_t k : {4u, 6u, 9u}) {
    Configuration config = split_config(block, 1024, 2048, 1, k);
    config.high_policy = HighPolicy::Cache;
    configs.push_back(config);
  }
  return configs;
}

TEST(StackPath, EqualsEachConfigurationAloneOnRandomStreams) {
  for (const bool mixed : {false, true}) {
    for (const bool invalidates : {false, true}) {
      const auto records = random_records(mixed ? 41 : 42, 30000, mixed, invalidates);
      const auto form = mixed ? formats::RecordForm::ExtendedDin : formats::RecordForm::Din;
      for (const bool per_level : {false, true}) {
        SCOPED_TRACE(::testing::Message() << "mixed " << mixed << " invalidates " << invalidates
                                          << " per_level " << per_level);
        expect_together_equals_alone(design_space(mixed ? 16 : 8), batches_of(records), form,
                                     per_level);
        expect_together_equals_alone(table1_grid(mixed ? 16 : 8), batches_of(records), form,
                                     per_level);
      }
    }
  }
}

TEST(StackPath, EqualsEachConfigurationAloneOnARenderedTrace) {
  testing::TempDir dir;
  const auto trace = dir / "render.din.zst";
  const auto rendered =
      testing::run_command(testing::shell_quoted(testing::program("tracer")) +
                           " render mountain --width 24 --height 18 --high-size 2k -q -o " +
                           testing::shell_quoted(trace));
  ASSERT_EQ(rendered.exit_code, 0) << rendered.err;
  auto reader = formats::TraceReader::open(trace.string());
  std::vector<Record> records;
  std::optional<formats::AnimationFrameMarker> marker;
  RecordBatch batch;
  while (reader->next(batch)) {
    if (batch.marker && !marker) marker = batch.marker;
    records.insert(records.end(), batch.records.begin(), batch.records.end());
  }
  ASSERT_TRUE(marker.has_value());
  ASSERT_GT(records.size(), 20000u);
  // The frame's records cut into animation frames of 6000 records, each
  // with the frame's marker (so K = auto as the tracer sized it).
  const auto batches = batches_of(records, [&](std::uint64_t frame) {
    formats::AnimationFrameMarker copy = *marker;
    copy.frame = frame;
    return copy;
  });
  // High caches that the mountain's high levels fit.
  auto fitting = [](std::vector<Configuration> configs) {
    for (Configuration& config : configs) {
      if (config.scheme == Scheme::Split && config.high_size < 2048) {
        config.high_size *= 4;
        config.size = config.high_size + config.low_size;
      }
    }
    return configs;
  };
  const std::vector<Configuration> configs = fitting(design_space(8));
  const std::vector<Configuration> grid = fitting(table1_grid(8));
  for (const bool per_level : {false, true}) {
    SCOPED_TRACE(::testing::Message() << "per_level " << per_level);
    expect_together_equals_alone(configs, batches, reader->form(), per_level);
    expect_together_equals_alone(grid, batches, reader->form(), per_level);
  }
}


TEST(SetStacks, WalkCountsTheFetchesThatReachEachSetCountAndThePlacesSearched) {
  // One set and two sets, both 2 deep. Blocks 0, 2, 0, 1:
  //   one set:  0 not kept (place 2), 2 not kept, 0 at place 1, 1 not kept
  //   two sets (reached by all four: none was on top of the one set):
  //     set 0: 0 not kept, 2 not kept, 0 at place 1; set 1: 1 not kept
  SetStacks stacks({{0, 2}, {1, 2}});
  for (const std::uint64_t block : {0u, 2u, 0u, 1u}) stacks.access(block);
  EXPECT_EQ(stacks.walk(0).visits, 4u);
  EXPECT_EQ(stacks.walk(0).places, 4u);  // one each (not kept: depth - 1 = 1; place 1)
  EXPECT_EQ(stacks.walk(1).visits, 4u);
  EXPECT_EQ(stacks.walk(1).places, 4u);
  // Block 1 again: on top of the one set, so the walk stops there.
  stacks.access(1);
  EXPECT_EQ(stacks.walk(0).visits, 5u);
  EXPECT_EQ(stacks.walk(1).visits, 4u);
}

// The sweep fed as run_sweep feeds it, in `parts` parts (each batch's parts
// in reverse order, so no part relies on another having run first).
TraceResult parted_sweep(const std::vector<Configuration>& configs,
                         const std::vector<RecordBatch>& batches, formats::RecordForm form,
                         bool per_level, std::size_t parts, std::size_t* part_count = nullptr) {
  Sweep sweep(configs, context_of(form), per_level, true);
  sweep.set_parts(parts);
  for (const RecordBatch& batch : batches) {
    sweep.begin_batch(batch);
    for (std::size_t part = sweep.part_count(); part-- > 0;) sweep.feed_part(batch, part);
  }
  if (part_count) *part_count = sweep.part_count();
  return sweep.finish();
}

void expect_results_equal(const TraceResult& parted, const TraceResult& one) {
  ASSERT_EQ(parted.rows.size(), one.rows.size());
  for (std::size_t i = 0; i < one.rows.size(); ++i) {
    expect_rows_equal(parted.rows[i], one.rows[i], fmt::format("row {}", i));
  }
  ASSERT_EQ(parted.animation_frame_rows.size(), one.animation_frame_rows.size());
  for (std::size_t i = 0; i < one.animation_frame_rows.size(); ++i) {
    EXPECT_EQ(parted.animation_frame_rows[i].frame, one.animation_frame_rows[i].frame) << i;
    EXPECT_EQ(parted.animation_frame_rows[i].row.config.size, one.animation_frame_rows[i].row.config.size) << i;
    expect_rows_equal(parted.animation_frame_rows[i].row, one.animation_frame_rows[i].row,
                      fmt::format("frame row {}", i));
  }
  ASSERT_EQ(parted.level_rows.size(), one.level_rows.size());
  for (std::size_t i = 0; i < one.level_rows.size(); ++i) {
    EXPECT_EQ(parted.level_rows[i].config.size, one.level_rows[i].config.size) << i;
    EXPECT_EQ(parted.level_rows[i].split_level, one.level_rows[i].split_level) << i;
    EXPECT_EQ(parted.level_rows[i].level, one.level_rows[i].level) << i;
    EXPECT_EQ(parted.level_rows[i].refs, one.level_rows[i].refs) << i;
    EXPECT_EQ(parted.level_rows[i].misses, one.level_rows[i].misses) << i;
  }
  EXPECT_EQ(parted.other_stream_records, one.other_stream_records);
  EXPECT_EQ(parted.notes, one.notes);
}

// Single LRU caches of one block size, 1k..32k x 1..8 ways: one stack group
// of 11 set counts.
std::vector<Configuration> one_stack_group(std::uint32_t block) {
  SweepOptions options;
  options.sizes = {1024, 2048, 4096, 8192, 16384, 32768};
  options.blocks = {block};
  options.assocs = {1, 2, 4, 8};
  options.policies = {ReplacementPolicy::Lru};
  return expand_configurations(options);
}

TEST(SweepParts, TwoThreeAndFourPartsGiveTheRowsOfOne) {
  for (const bool mixed : {false, true}) {
    for (const bool invalidates : {false, true}) {
      // 36000 records: 12 batches, so the parts are shared out anew by
      // measured time (at batches 4 and 8) while the counts go on.
      const auto records = random_records(mixed ? 51 : 52, 36000, mixed, invalidates);
      const auto batches = batches_of(records);
      const auto form = mixed ? formats::RecordForm::ExtendedDin : formats::RecordForm::Din;
      for (const bool per_level : {false, true}) {
        for (const auto& configs : {one_stack_group(mixed ? 16 : 8), design_space(mixed ? 16 : 8),
                                    table1_grid(mixed ? 16 : 8)}) {
          const TraceResult one = parted_sweep(configs, batches, form, per_level, 1);
          for (const std::size_t parts : {2u, 3u, 4u}) {
            SCOPED_TRACE(::testing::Message()
                         << "mixed " << mixed << " invalidates " << invalidates << " per_level "
                         << per_level << " configs " << configs.size() << " parts " << parts);
            std::size_t part_count = 0;
            expect_results_equal(parted_sweep(configs, batches, form, per_level, parts, &part_count),
                                 one);
            EXPECT_GT(part_count, 1u);
          }
        }
      }
    }
  }
}

TEST(SweepParts, OneStackGroupIsCutIntoPiecesAcrossParts) {
  // One key, so more than one part means the group was cut.
  const auto records = random_records(53, 12000, false, false);
  std::size_t part_count = 0;
  parted_sweep(one_stack_group(8), batches_of(records), formats::RecordForm::Din, false, 2,
               &part_count);
  EXPECT_EQ(part_count, 2u);
}

TEST(SweepParts, HighLevelsThatDoNotFitAreTheSameErrorInEveryPart) {
  // Split under retain, K = 12 (levels 0..11: up to 2048 blocks a frame),
  // several low sizes: one stack group cut into pieces. The two high caches
  // that do not fit (1024 bytes with the smallest low cache, 512 bytes with
  // the largest) fall in different pieces, yet every piece stops at the
  // same record naming the tightest, as one part does.
  std::vector<Configuration> configs;
  for (const std::uint64_t low : {256u, 512u, 1024u, 2048u, 4096u, 8192u, 16384u}) {
    const std::uint64_t high = low == 256 ? 1024 : low == 16384 ? 512 : 16384;
    Configuration config = split_config(8, high, low, 1, 12);
    config.high_policy = HighPolicy::Retain;
    configs.push_back(config);
  }
  const auto records = random_records(54, 12000, false, false);
  const auto batches = batches_of(records);
  const auto message_of = [&](std::size_t parts) {
    try {
      parted_sweep(configs, batches, formats::RecordForm::Din, false, parts);
    } catch (const base::UsageError& error) {
      return std::string(error.what());
    }
    return std::string("no error");
  };
  const std::string one = message_of(1);
  EXPECT_NE(one.find("512-byte high cache"), std::string::npos) << one;
  for (const std::size_t parts : {2u, 3u, 4u}) EXPECT_EQ(message_of(parts), one) << parts;
}

}  // namespace
}  // namespace nodetrace::cachesim
