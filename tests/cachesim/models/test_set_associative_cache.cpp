// The node cache against hand-worked answers and against the Dinero-IV-exact
// engine (the reference) on random streams and the golden kd trace.
#include <gtest/gtest.h>

#include <random>
#include <vector>
#include <sstream>

#include "nodetrace/cachesim/dinero/engine.hpp"
#include "nodetrace/cachesim/models/set_associative_cache.hpp"
#include "nodetrace/cachesim/sweep/sweep.hpp"
#include "nodetrace/base/error.hpp"
#include "test_support.hpp"

namespace nodetrace::cachesim {
namespace {

using formats::AccessType;
using formats::Record;

TEST(SetAssociativeCache, DirectMappedConflictsAndHits) {
  SetAssociativeCache cache({64, 8, 1, ReplacementPolicy::Lru});  // 8 sets
  EXPECT_TRUE(cache.access(0));
  EXPECT_FALSE(cache.access(0));
  EXPECT_TRUE(cache.access(8));   // same set as 0: evicts it
  EXPECT_TRUE(cache.access(0));
  EXPECT_TRUE(cache.access(1));
  EXPECT_FALSE(cache.access(0));
}

TEST(SetAssociativeCache, LruKeepsTheRecentlyUsedWay) {
  SetAssociativeCache cache({16, 8, 2, ReplacementPolicy::Lru});  // one set of 2 ways
  EXPECT_TRUE(cache.access(1));
  EXPECT_TRUE(cache.access(2));
  EXPECT_FALSE(cache.access(1));  // 1 most recent
  EXPECT_TRUE(cache.access(3));   // evicts 2
  EXPECT_FALSE(cache.access(1));
  EXPECT_TRUE(cache.access(2));
}

TEST(SetAssociativeCache, FifoEvictsTheOldestFillEvenWhenUsed) {
  SetAssociativeCache cache({16, 8, 2, ReplacementPolicy::Fifo});
  EXPECT_TRUE(cache.access(1));
  EXPECT_TRUE(cache.access(2));
  EXPECT_FALSE(cache.access(1));
  EXPECT_TRUE(cache.access(3));  // evicts 1, the oldest fill
  EXPECT_TRUE(cache.access(1));
  EXPECT_FALSE(cache.access(3));
}

TEST(SetAssociativeCache, InvalidateFreesTheWay) {
  SetAssociativeCache cache({16, 8, 2, ReplacementPolicy::Lru});
  cache.access(1);
  cache.access(2);
  cache.invalidate(1);
  EXPECT_TRUE(cache.access(3));   // takes the freed way, 2 stays
  EXPECT_FALSE(cache.access(2));
  EXPECT_TRUE(cache.access(1));
}

// Dinero IV's random: each cache draws its own sequence (glibc's random()
// after srandom(1)), so a cache's misses do not depend on another cache fed
// between its accesses, and differ from LRU's on the same blocks.
TEST(SetAssociativeCache, RandomDrawsASequenceOfItsOwn) {
  std::mt19937_64 generator(7);
  std::vector<std::uint64_t> blocks(5000);
  for (std::uint64_t& block : blocks) block = generator() % 100;
  SetAssociativeCache alone({256, 8, 8, ReplacementPolicy::Random});
  std::uint64_t alone_misses = 0;
  for (const std::uint64_t block : blocks) alone_misses += alone.access(block);
  SetAssociativeCache first({256, 8, 8, ReplacementPolicy::Random});
  SetAssociativeCache second({256, 8, 8, ReplacementPolicy::Random});
  std::uint64_t first_misses = 0;
  for (const std::uint64_t block : blocks) {
    first_misses += first.access(block);
    second.access(block + 1000);  // its misses draw from its own sequence
  }
  EXPECT_EQ(first_misses, alone_misses);
  SetAssociativeCache lru({256, 8, 8, ReplacementPolicy::Lru});
  std::uint64_t lru_misses = 0;
  for (const std::uint64_t block : blocks) lru_misses += lru.access(block);
  EXPECT_NE(alone_misses, lru_misses);
  EXPECT_GE(alone_misses, 100u);  // every distinct block misses once at least
}

TEST(SetAssociativeCache, RefusesThePoliciesOfOtherModels) {
  EXPECT_THROW(SetAssociativeCache({256, 8, 4, ReplacementPolicy::Plru}), base::UsageError);
  EXPECT_THROW(SetAssociativeCache({256, 8, 4, ReplacementPolicy::Opt}), base::UsageError);
}

TEST(SetAssociativeCache, RejectsImpossibleGeometry) {
  EXPECT_THROW(SetAssociativeCache({1000, 8, 1, ReplacementPolicy::Lru}), base::UsageError);
  EXPECT_THROW(SetAssociativeCache({1024, 12, 1, ReplacementPolicy::Lru}), base::UsageError);
  EXPECT_THROW(SetAssociativeCache({1024, 8, 3, ReplacementPolicy::Lru}), base::UsageError);
  EXPECT_THROW(SetAssociativeCache({64, 128, 1, ReplacementPolicy::Lru}), base::UsageError);
}

// Misses of `records` in a single cache, by the engine (the reference).
std::uint64_t engine_misses(const std::vector<Record>& records, const CacheGeometry& geometry,
                            formats::RecordForm form, std::uint64_t* fetches = nullptr) {
  CacheConfig cache;
  cache.size = geometry.size;
  cache.block_size = geometry.block_size;
  cache.assoc = geometry.assoc;
  cache.replacement = geometry.replacement;
  Hierarchy hierarchy(single_level(cache));
  hierarchy.access_batch(records, form);
  hierarchy.finish();
  const Stats& stats = hierarchy.stats(1, CacheKind::Unified);
  if (fetches) *fetches = stats.demand_fetches();
  return stats.demand_misses();
}

// The same by a single-scheme sweep of the node cache.
ResultRow sweep_single(const std::vector<Record>& records, const CacheGeometry& geometry,
                       formats::RecordForm form) {
  Configuration config;
  config.size = geometry.size;
  config.block = geometry.block_size;
  config.assoc = geometry.assoc;
  config.policy = geometry.replacement;
  TraceContext context;
  context.trace = "t";
  context.form = form;
  Sweep sweep({config}, context, false);
  formats::RecordBatch batch;
  batch.records = records;
  sweep.feed(batch);
  return sweep.finish().rows.at(0);
}

std::vector<Record> random_stream(std::uint64_t seed, std::size_t count, bool mixed) {
  std::mt19937_64 generator(seed);
  std::vector<Record> records(count);
  for (Record& record : records) {
    // Mostly a small working set with some far references, so hits and
    // every kind of miss occur.
    const std::uint64_t region = generator() % 10 == 0 ? 1u << 20 : 0;
    record.address = region + (generator() % 4096) * (mixed ? 1 : 8);
    record.size = mixed ? 1 + static_cast<std::uint32_t>(generator() % 16) : 8;
    if (mixed) {
      const auto draw = generator() % 20;
      record.type = draw < 12   ? AccessType::Read
                    : draw < 17 ? AccessType::Write
                    : draw < 19 ? AccessType::InstructionFetch
                                : AccessType::Misc;
    }
    record.tag = static_cast<formats::Tag>(generator() % 20);
  }
  return records;
}

TEST(SetAssociativeCache, EqualsTheEngineOnRandomStreams) {
  const std::vector<std::uint32_t> assocs{1, 2, 4, 8, 32, 0};  // 0: fully associative
  for (const bool mixed : {false, true}) {
    for (const auto form : {formats::RecordForm::Din, formats::RecordForm::ExtendedDin}) {
      const std::vector<Record> records = random_stream(mixed ? 11 : 12, 40000, mixed);
      // Random draws Dinero IV's sequence, so it too equals the engine;
      // 64 ways and full take the policy cache's recency lists.
      for (const auto policy : {ReplacementPolicy::Lru, ReplacementPolicy::Fifo, ReplacementPolicy::Random}) {
        for (const std::uint32_t block : {4u, 8u, 32u}) {
          for (const std::uint32_t assoc : assocs) {
            CacheGeometry geometry{2048, block, assoc == 0 ? 2048 / block : assoc, policy};
            SCOPED_TRACE(::testing::Message()
                         << "mixed " << mixed << " form " << formats::form_name(form)
                         << " policy " << policy_name(policy) << " block " << block
                         << " assoc " << geometry.assoc);
            std::uint64_t fetches = 0;
            const std::uint64_t misses = engine_misses(records, geometry, form, &fetches);
            const ResultRow row = sweep_single(records, geometry, form);
            EXPECT_EQ(row.misses, misses);
            EXPECT_EQ(row.fetches, fetches);
            EXPECT_EQ(row.refs, records.size());
          }
        }
      }
    }
  }
}

// The split scheme under `cache` is two independent caches: each equals the
// engine fed only its levels. Batches of mixed records take the general path,
// node-only batches the fast one, and --per-level always the general one.
TEST(SetAssociativeCache, SplitCacheHalvesEqualTheEngineOnFilteredStreams) {
  for (const bool mixed : {false, true}) {
    const std::vector<Record> records = random_stream(mixed ? 21 : 22, 30000, mixed);
    for (const std::uint32_t assoc : {1u, 2u, 0u}) {
      for (const auto policy : {ReplacementPolicy::Lru, ReplacementPolicy::Fifo, ReplacementPolicy::Random}) {
        Configuration config;
        config.scheme = Scheme::Split;
        config.high_policy = HighPolicy::Cache;
        config.high_size = 1024;
        config.low_size = 2048;
        config.size = 3072;
        config.block = 16;
        config.assoc = assoc == 0 ? 2048 / 16 : assoc;
        config.high_assoc = assoc == 0 ? 1024 / 16 : (assoc == 1 ? 2 : 1);
        config.policy = policy;
        config.split_level = 7;
        std::vector<Record> high;
        std::vector<Record> low;
        for (const Record& record : records) (record.tag < 7 ? high : low).push_back(record);
        const auto form = mixed ? formats::RecordForm::ExtendedDin : formats::RecordForm::Din;
        std::uint64_t high_fetches = 0;
        std::uint64_t low_fetches = 0;
        const std::uint64_t high_misses = engine_misses(
            high, {1024, 16, config.high_assoc, policy}, form, &high_fetches);
        const std::uint64_t low_misses =
            engine_misses(low, {2048, 16, config.assoc, policy}, form, &low_fetches);
        for (const bool per_level : {false, true}) {
          SCOPED_TRACE(::testing::Message() << "mixed " << mixed << " assoc " << config.assoc
                                            << " policy " << policy_name(policy)
                                            << " per_level " << per_level);
          TraceContext context;
          context.trace = "t";
          context.form = form;
          context.tags_are_levels = true;
          Sweep sweep({config}, context, per_level);
          formats::RecordBatch batch;
          batch.records = records;
          sweep.feed(batch);
          const ResultRow row = sweep.finish().rows.at(0);
          EXPECT_EQ(row.high_refs, high.size());
          EXPECT_EQ(row.low_refs, low.size());
          EXPECT_EQ(row.high_misses, high_misses);
          EXPECT_EQ(row.low_misses, low_misses);
          EXPECT_EQ(row.fetches, high_fetches + low_fetches);
        }
      }
    }
  }
}

// Retain on the fast path (node-only batches) and on the general path
// (--per-level) gives the same loads and low misses.
TEST(SetAssociativeCache, RetainFastAndGeneralPathsAgree) {
  const std::vector<Record> records = random_stream(31, 50000, false);
  for (const std::uint32_t assoc : {1u, 4u}) {
    Configuration config;
    config.scheme = Scheme::Split;
    config.high_policy = HighPolicy::Retain;
    config.high_size = 32768;
    config.low_size = 4096;
    config.size = 36864;
    config.block = 8;
    config.assoc = assoc;
    config.split_level = 10;
    ResultRow rows[2];
    for (const bool per_level : {false, true}) {
      TraceContext context;
      context.trace = "t";
      context.tags_are_levels = true;
      Sweep sweep({config}, context, per_level);
      for (std::size_t begin = 0; begin < records.size(); begin += 7000) {
        formats::RecordBatch batch;
        batch.records.assign(records.begin() + static_cast<std::ptrdiff_t>(begin),
                             records.begin() + static_cast<std::ptrdiff_t>(
                                                   std::min(records.size(), begin + 7000)));
        batch.first_record = begin;
        if (begin % 14000 == 0) batch.marker = formats::AnimationFrameMarker{};  // new animation frame
        sweep.feed(batch);
      }
      rows[per_level] = sweep.finish().rows.at(0);
    }
    EXPECT_GT(*rows[0].high_loads, 0u);
    EXPECT_EQ(rows[0].high_loads, rows[1].high_loads);
    EXPECT_EQ(rows[0].low_misses, rows[1].low_misses);
    EXPECT_EQ(rows[0].high_refs, rows[1].high_refs);
    EXPECT_GT(rows[0].low_misses, 0u);
  }
}

// The golden kd trace's records, decompressed by the zstd program.
std::vector<Record> golden_kd_records(const std::filesystem::path& shared) {
  const auto result = testing::run_command(
      "zstd -dc '" + (shared / "dinero-golden" / "kd-bfl-s1.din.zst").string() + "'");
  EXPECT_EQ(result.exit_code, 0) << result.err;
  std::vector<Record> records;
  std::istringstream lines(result.out);
  int label = 0;
  std::string address;
  unsigned level = 0;
  while (lines >> label >> address >> level) {
    Record record;
    record.type = static_cast<AccessType>(label);
    record.address = std::stoull(address, nullptr, 16);
    record.tag = static_cast<formats::Tag>(level);
    records.push_back(record);
  }
  return records;
}

TEST(SetAssociativeCache, GoldenKdMissesOfDineroIV) {
  NODETRACE_SHARED_OR_SKIP(shared);
  const std::vector<Record> records = golden_kd_records(shared);
  ASSERT_EQ(records.size(), 200000u);
  struct Case {
    CacheGeometry geometry;
    std::uint64_t misses;  // from dinero-golden/kd1-*.out
  };
  const std::vector<Case> cases{
      {{4096, 8, 1, ReplacementPolicy::Lru}, 0},
      {{8192, 8, 1, ReplacementPolicy::Lru}, 39930},
      {{16384, 8, 1, ReplacementPolicy::Lru}, 0},
      {{8192, 8, 4, ReplacementPolicy::Lru}, 0},
      {{8192, 8, 4, ReplacementPolicy::Fifo}, 0},
  };
  // The numbers other than 8k direct mapped are read from the .out files.
  const std::vector<std::string> names{"kd1-d4k-b8-a1", "kd1-d8k-b8-a1", "kd1-d16k-b8-a1",
                                       "kd1-d8k-b8-a4-lru", "kd1-d8k-b8-a4-fifo"};
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const std::string out =
        testing::read_file(shared / "dinero-golden" / (names[i] + ".out"));
    const auto at = out.find(" Demand Misses");
    ASSERT_NE(at, std::string::npos) << names[i];
    const std::uint64_t golden = std::stoull(out.substr(at + 14));
    if (cases[i].misses != 0) {
      EXPECT_EQ(golden, cases[i].misses) << names[i];
    }
    const ResultRow row = sweep_single(records, cases[i].geometry, formats::RecordForm::Din);
    EXPECT_EQ(row.fetches, 200000u) << names[i];
    EXPECT_EQ(row.misses, golden) << names[i];
  }
}

}  // namespace
}  // namespace nodetrace::cachesim
