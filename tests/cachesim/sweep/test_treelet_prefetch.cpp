// The treelet prefetcher (`cachesim run --prefetch treelet`, issue 51) on
// batches made here, markers carrying maps: counts worked out by hand, the
// range a miss prefetches, the errors, and the sweep against the reference
// model (tests/reference) on random traces, maps and configurations.
#include <gtest/gtest.h>

#include <random>

#include "models/treelet_prefetcher.hpp"
#include "nodetrace/base/error.hpp"
#include "nodetrace/cachesim/sweep/sweep.hpp"
#include "reference_cache.hpp"

namespace nodetrace::cachesim {
namespace {

using formats::Record;
using formats::RecordBatch;
using formats::TreeletMap;

Record node(std::uint64_t address, formats::Tag level = 0) {
  Record record;
  record.address = address;
  record.size = 8;
  record.tag = level;
  return record;
}

TraceContext context() {
  TraceContext context;
  context.trace = "t.xdin.zst";
  context.source_name = "t.xdin.zst";
  context.form = formats::RecordForm::ExtendedDin;
  context.tags_are_levels = true;
  return context;
}

// One animation frame's batch, its marker carrying `map` (nullopt: none).
RecordBatch frame_batch(std::uint64_t frame, std::optional<TreeletMap> map, std::vector<Record> records,
                        std::uint64_t first_record = 0) {
  RecordBatch batch;
  batch.marker.emplace();
  batch.marker->frame = frame;
  batch.marker->treelets = std::move(map);
  batch.records = std::move(records);
  batch.first_record = first_record;
  return batch;
}

Configuration lru(std::uint64_t size, std::uint32_t assoc, PrefetchSpec prefetch) {
  Configuration config;
  config.size = size;
  config.block = 8;
  config.assoc = assoc;
  config.prefetch = prefetch;
  return config;
}

TreeletMap map_of(std::vector<formats::TreeletRange> ranges) { return TreeletMap{std::move(ranges)}; }

// The row of `config` over one animation frame of `records` with `map`.
ResultRow run_frame(const Configuration& config, const TreeletMap& map, std::vector<Record> records) {
  Sweep sweep({config}, context(), false);
  sweep.feed(frame_batch(0, map, std::move(records)));
  const TraceResult result = sweep.finish();
  EXPECT_EQ(result.rows.size(), 1u);  // the run without the prefetcher is not a row
  return result.rows.at(0);
}

TEST(TreeletPrefetch, AMissFetchesTheRestOfItsTreeletAndLaterHitsAreUseful) {
  // 64-byte fully associative LRU cache, treelets [0, 32) and [32, 64).
  // Reads 0, 8, 16, 24: 0 misses and prefetches 8, 16, 24 (3), the others
  // hit them (3 useful). Then 40: a miss prefetching 48, 56 (2), unused.
  // Without the prefetcher: 5 misses; with it 2: coverage 3/5.
  const ResultRow row = run_frame(lru(64, 8, {TreeletPrefetch::Treelet, 0}), map_of({{0, 32}, {32, 32}}),
                                 {node(0), node(8), node(16), node(24), node(40)});
  EXPECT_EQ(row.misses, 2u);
  EXPECT_EQ(row.fetches, 5u);
  ASSERT_TRUE(row.prefetch);
  EXPECT_EQ(row.prefetch->counts.prefetches, 5u);
  EXPECT_EQ(row.prefetch->counts.useful, 3u);
  EXPECT_EQ(row.prefetch->misses_without_prefetch, 5u);
  EXPECT_EQ(row.prefetch->fetched_blocks, 7u);
}

TEST(TreeletPrefetch, BytesLimitTheRangeFromTheMissedBlock) {
  // treelet:16 from the missed block at 0: blocks 0 and 8, so 8 only.
  const ResultRow row =
      run_frame(lru(64, 8, {TreeletPrefetch::Treelet, 16}), map_of({{0, 64}}), {node(0), node(8), node(16), node(24)});
  EXPECT_EQ(row.prefetch->counts.prefetches, 2u);  // after 0: 8; after 16: 24
  EXPECT_EQ(row.prefetch->counts.useful, 2u);
  EXPECT_EQ(row.misses, 2u);
}

TEST(TreeletPrefetch, APrefetchThatEvictsIsCountedUselessAndCoverageFalls) {
  // Direct mapped, 2 sets of 8 bytes. Treelet [0, 16): a miss on 0
  // prefetches 8 (set 1), evicting 24, which is then missed. Reads: 24, 0, 24.
  // Without: 24 m, 0 m, 24 h = 2 misses; with: 24 m, 0 m (+8), 24 m = 3.
  const ResultRow row = run_frame(lru(16, 1, {TreeletPrefetch::Treelet, 0}), map_of({{0, 16}}), {node(24), node(0), node(24)});
  EXPECT_EQ(row.misses, 3u);
  EXPECT_EQ(row.prefetch->misses_without_prefetch, 2u);
  EXPECT_EQ(row.prefetch->counts.prefetches, 1u);
  EXPECT_EQ(row.prefetch->counts.useful, 0u);
}

TEST(TreeletPrefetch, TreeletLowLeavesTheHighCacheDemandFetched) {
  Configuration config;
  config.scheme = Scheme::Split;
  config.size = 128;
  config.high_size = 64;
  config.low_size = 64;
  config.block = 8;
  config.assoc = 8;
  config.high_assoc = 8;
  config.high_policy = HighPolicy::Cache;
  config.split_level = 1;
  // Level 0 at 0 (high), level 1 at 64 (low); one treelet each of 32 bytes.
  const std::vector<Record> records{node(0, 0), node(8, 0), node(64, 1), node(72, 1)};
  const TreeletMap map = map_of({{0, 32}, {64, 32}});
  config.prefetch = {TreeletPrefetch::Treelet, 0};
  const ResultRow both_row = run_frame(config, map, records);
  EXPECT_EQ(both_row.high_misses, 1u);
  EXPECT_EQ(both_row.low_misses, 1u);
  EXPECT_EQ(both_row.prefetch->counts.prefetches, 6u);
  config.prefetch = {TreeletPrefetch::TreeletLow, 0};
  const ResultRow low_row = run_frame(config, map, records);
  EXPECT_EQ(low_row.high_misses, 2u);
  EXPECT_EQ(low_row.low_misses, 1u);
  EXPECT_EQ(low_row.prefetch->counts.prefetches, 3u);
  EXPECT_EQ(low_row.prefetch->counts.useful, 1u);
}

TEST(TreeletPrefetch, RangeIsTheTreeletHoldingTheBlockOrBeginningInIt) {
  const TreeletMap map = map_of({{16, 16}, {40, 100}});
  // Block [0, 32) holds no treelet's first byte at 0; treelet [16, 32) begins inside it.
  auto range = treelet_prefetch_range(map, 0, 32, 0);
  ASSERT_TRUE(range);
  EXPECT_EQ(range->end, 32u);
  // Block [32, 40): in the gap, and no treelet begins inside it.
  EXPECT_FALSE(treelet_prefetch_range(map, 32, 8, 0));
  // Block [64, 128) in [40, 140), cut at 64 bytes: up to 128.
  range = treelet_prefetch_range(map, 64, 64, 64);
  ASSERT_TRUE(range);
  EXPECT_EQ(range->end, 128u);
  EXPECT_FALSE(treelet_prefetch_range(map, 140, 8, 0));
}

TEST(TreeletPrefetch, ATraceWithoutAMapIsAUsageErrorNamingTheLayout) {
  Sweep sweep({lru(64, 8, {TreeletPrefetch::Treelet, 0})}, context(), false);
  try {
    sweep.feed(frame_batch(0, std::nullopt, {node(0)}));
    FAIL() << "expected a usage error";
  } catch (const base::UsageError& error) {
    EXPECT_NE(std::string(error.what()).find("tracer render --layout treelet"), std::string::npos) << error.what();
  }
}

TEST(TreeletPrefetch, AMapThatOverlapsItselfIsBadData) {
  Sweep sweep({lru(64, 8, {TreeletPrefetch::Treelet, 0})}, context(), false);
  EXPECT_THROW(sweep.feed(frame_batch(0, map_of({{0, 32}, {16, 32}}), {node(0)})), base::FormatError);
}

TEST(TreeletPrefetch, SpecsParseAndRefuseWhatIsNotAPowerOfTwo) {
  EXPECT_EQ(parse_prefetch("treelet"), (PrefetchSpec{TreeletPrefetch::Treelet, 0}));
  EXPECT_EQ(parse_prefetch("treelet-low:4k"), (PrefetchSpec{TreeletPrefetch::TreeletLow, 4096}));
  EXPECT_EQ(prefetch_name(parse_prefetch("treelet:1k")), "treelet:1024");
  EXPECT_THROW(parse_prefetch("treelet:3k"), base::UsageError);
  EXPECT_THROW(parse_prefetch("treelet:0"), base::UsageError);
  EXPECT_THROW(parse_prefetch("treelet:x"), base::UsageError);
  EXPECT_THROW(parse_prefetch("tree"), base::UsageError);
}

// --- Against the reference model -----------------------------------------

const ReplacementPolicy kPolicies[] = {ReplacementPolicy::Lru,   ReplacementPolicy::Fifo,  ReplacementPolicy::Random,
                                       ReplacementPolicy::Plru,  ReplacementPolicy::Srrip, ReplacementPolicy::Brrip,
                                       ReplacementPolicy::Drrip};
const reference::Policy kReferencePolicies[] = {reference::Policy::Lru,   reference::Policy::Fifo,
                                                reference::Policy::Random, reference::Policy::Plru,
                                                reference::Policy::Srrip, reference::Policy::Brrip,
                                                reference::Policy::Drrip};

// A random map over [0, span): treelets with gaps, a few bytes to 1 KB each.
TreeletMap random_map(std::mt19937_64& random, std::uint64_t span) {
  TreeletMap map;
  std::uint64_t at = random() % 64;
  while (at < span) {
    const std::uint64_t bytes = 1 + random() % 1024;
    map.treelets.push_back({at, bytes});
    at += bytes + (random() % 3 == 0 ? random() % 128 : 0);
  }
  return map;
}

TEST(TreeletPrefetch, EqualsTheReferenceModelOnRandomCases) {
  std::mt19937_64 random(5100001);
  for (int c = 0; c < 400; ++c) {
    SCOPED_TRACE(testing::Message() << "case " << c);
    const std::uint64_t span = std::uint64_t{1} << (8 + random() % 6);
    const std::uint32_t frames = 1 + static_cast<std::uint32_t>(random() % 3);
    reference::TraceFacts facts;
    std::vector<RecordBatch> batches;
    for (std::uint32_t f = 0; f < frames; ++f) {
      const bool has_map = f == 0 || random() % 4 != 0;
      std::optional<TreeletMap> map;
      if (has_map) map = random_map(random, span);
      std::vector<Record> records;
      const std::size_t count = 50 + random() % 400;
      std::uint64_t address = random() % span;
      for (std::size_t i = 0; i < count; ++i) {
        // Mostly walks forward (a traversal), sometimes jumps.
        address = random() % 5 == 0 ? random() % span : (address + 8 * (random() % 4)) % span;
        Record record = node(address & ~std::uint64_t{7}, static_cast<formats::Tag>(random() % 6));
        if (random() % 40 == 0) record.type = formats::AccessType::Invalidate;
        records.push_back(record);
        reference::TraceRecord fact;
        fact.address = record.address;
        fact.size = record.size;
        fact.type = static_cast<int>(record.type);
        fact.level = record.tag;
        fact.frame = f;
        facts.records.push_back(fact);
      }
      if (has_map) {
        std::vector<reference::Treelet> treelets;
        for (const auto& range : map->treelets) treelets.push_back({range.first, range.bytes});
        facts.treelets.emplace_back(std::move(treelets));
      } else {
        facts.treelets.emplace_back(std::nullopt);
      }
      const std::uint64_t first_record = facts.records.size() - count;
      batches.push_back(frame_batch(f, std::move(map), std::move(records), first_record));
    }
    facts.frames = frames;

    const std::size_t p = random() % 7;
    Configuration config;
    reference::Config expected;
    config.block = std::uint32_t{8} << (random() % 3);
    config.policy = kPolicies[p];
    expected.policy = kReferencePolicies[p];
    expected.block = config.block;
    const std::uint32_t ways = std::uint32_t{1} << (random() % 4);
    const std::uint64_t cache = std::uint64_t{config.block} * ways << (random() % 4);
    config.assoc = ways;
    expected.assoc = ways;
    const int scheme = static_cast<int>(random() % 3);  // single, split retain, split cache
    if (scheme == 0) {
      config.size = cache;
    } else {
      config.scheme = Scheme::Split;
      config.low_size = cache;
      config.high_size = cache;
      config.size = 2 * cache;
      config.high_assoc = ways;
      config.high_policy = scheme == 1 ? HighPolicy::Retain : HighPolicy::Cache;
      config.split_level = static_cast<std::uint32_t>(random() % 3);
      // Retain holds every high block of a frame.
      if (scheme == 1) config.high_size = span;
      expected.split = true;
      expected.retain = scheme == 1;
      expected.low_size = config.low_size;
      expected.high_size = config.high_size;
      expected.high_assoc = ways;
      expected.split_level = config.split_level;
      expected.count_loads = false;
    }
    expected.size = config.size;
    const bool low_only = random() % 3 == 0;
    const std::uint64_t bytes = random() % 2 == 0 ? 0 : std::uint64_t{8} << (random() % 8);
    config.prefetch = {low_only ? TreeletPrefetch::TreeletLow : TreeletPrefetch::Treelet, bytes};
    expected.prefetch = true;
    expected.prefetch_low = low_only;
    expected.prefetch_bytes = bytes;

    Sweep sweep({config}, context(), false);
    for (const RecordBatch& batch : batches) sweep.feed(batch);
    const ResultRow row = sweep.finish().rows.at(0);
    const reference::Result with = reference::simulate(facts, expected);
    reference::Config without_config = expected;
    without_config.prefetch = false;
    const reference::Result without = reference::simulate(facts, without_config);
    ASSERT_FALSE(with.high_levels_do_not_fit);
    EXPECT_EQ(row.fetches, with.total.fetches);
    EXPECT_EQ(row.misses, with.total.misses);
    EXPECT_EQ(row.high_misses, with.total.high_misses);
    EXPECT_EQ(row.low_misses, with.total.low_misses);
    ASSERT_TRUE(row.prefetch);
    EXPECT_EQ(row.prefetch->counts.prefetches, with.total.prefetches);
    EXPECT_EQ(row.prefetch->counts.useful, with.total.useful_prefetches);
    EXPECT_EQ(row.prefetch->misses_without_prefetch, without.total.misses);
    // The properties: useful ones are prefetches; the traffic is demand fetches plus prefetches.
    EXPECT_LE(row.prefetch->counts.useful, row.prefetch->counts.prefetches);
    const std::uint64_t demand = config.scheme == Scheme::Single ? row.misses
                                 : row.low_misses + (config.high_policy == HighPolicy::Retain
                                                         ? row.high_loads.value_or(0)
                                                         : row.high_misses);
    EXPECT_EQ(row.prefetch->fetched_blocks, demand + row.prefetch->counts.prefetches);
    if (HasFailure()) return;
  }
}

}  // namespace
}  // namespace nodetrace::cachesim
