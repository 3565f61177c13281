// The replacement policies Dinero IV does not have (plru, srrip, brrip,
// drrip, opt) against the reference model (tests/reference/reference_cache.hpp),
// written apart from the engine and as plainly as possible: per-set arrays,
// and for opt a look ahead over the whole stream. On 1,200 seeded random traces and configurations (sizes,
// ways 1 to full, blocks, both schemes, invalidations) the sweep's counts
// must equal the reference's exactly. Then the properties every policy
// must have, and OPT's curve against single runs.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <random>
#include <vector>

#include "nodetrace/cachesim/sweep/curve.hpp"
#include "nodetrace/cachesim/sweep/sweep.hpp"
#include "nodetrace/base/error.hpp"
#include "reference_cache.hpp"
#include "test_support.hpp"

namespace nodetrace::cachesim {
namespace {

using formats::AccessType;
using formats::Record;

struct Counts {
  std::uint64_t high_misses = 0;
  std::uint64_t low_misses = 0;
  std::uint64_t high_loads = 0;
};

std::uint64_t block_of(const Record& record, std::uint32_t block) { return (record.address & ~std::uint64_t{3}) / block; }

// The reference model's counts (tests/reference) of `config` on din records
// tagged with levels: one animation frame, K given.
Counts reference_counts(const Configuration& config, const std::vector<Record>& records) {
  reference::TraceFacts trace;
  for (const Record& record : records) {
    reference::TraceRecord r;
    r.address = record.address & ~std::uint64_t{3};  // din: Dinero IV's address and size
    r.size = 4;
    r.type = static_cast<int>(record.type);
    r.level = record.tag;
    trace.records.push_back(r);
  }
  reference::Config ref;
  ref.split = config.scheme == Scheme::Split;
  ref.size = config.size;
  ref.block = config.block;
  ref.assoc = config.assoc;
  ref.policy = *reference::policy_named(policy_name(config.policy));
  ref.retain = config.high_policy == HighPolicy::Retain;
  ref.high_size = config.high_size;
  ref.low_size = config.low_size;
  ref.high_assoc = config.high_assoc;
  ref.split_level = config.split_level;
  const reference::Counts counts = reference::simulate(trace, ref).total;
  return {counts.high_misses, ref.split ? counts.low_misses : counts.misses, counts.high_loads};
}

ResultRow sweep_row(const Configuration& config, const std::vector<Record>& records) {
  TraceContext context;
  context.trace = "t";
  context.form = formats::RecordForm::Din;
  context.tags_are_levels = true;
  Sweep sweep({config}, context, false);
  formats::RecordBatch batch;
  batch.records = records;
  sweep.feed(batch);
  return sweep.finish().rows.at(0);
}

// Node fetches with locality over a universe about `spread` blocks wide,
// some invalidations when `invalidations`.
std::vector<Record> random_records(std::mt19937_64& random, std::size_t count, std::uint64_t spread,
                                   std::uint32_t block, bool invalidations) {
  std::vector<Record> records(count);
  std::uint64_t at = 0;
  for (Record& record : records) {
    at = random() % 6 == 0 ? random() % spread : (at + random() % 5) % spread;
    record.address = at * block + (random() % block & ~std::uint64_t{3});
    record.size = 4;
    record.tag = static_cast<formats::Tag>(random() % 12);
    record.type = invalidations && random() % 50 == 0 ? AccessType::Invalidate : AccessType::Read;
  }
  return records;
}

constexpr ReplacementPolicy kPolicies[] = {ReplacementPolicy::Lru,   ReplacementPolicy::Fifo,
                                           ReplacementPolicy::Plru,  ReplacementPolicy::Srrip,
                                           ReplacementPolicy::Brrip, ReplacementPolicy::Drrip,
                                           ReplacementPolicy::Opt};

TEST(ReplacementPolicies, EqualTheReferenceModelOnRandomTracesAndConfigurations) {
  // What the seeds covered, counted from the configurations checked, so
  // that a generator that stopped drawing some of them fails here.
  std::map<ReplacementPolicy, std::size_t> by_policy;
  std::size_t split_retained = 0;
  std::size_t split_cached = 0;
  for (std::uint64_t seed = 1; seed <= 1200; ++seed) {
    std::mt19937_64 random(seed);
    Configuration config;
    config.policy = kPolicies[random() % std::size(kPolicies)];
    config.block = 4u << (random() % 4);                      // 4 .. 32
    const std::uint64_t blocks = std::uint64_t{2} << (random() % 9);  // 2 .. 512
    const std::uint32_t ways_choices[] = {1, 2, 4, 8, 16, 32, 64, 0};
    const std::uint32_t ways = ways_choices[random() % std::size(ways_choices)];
    config.scheme = random() % 3 == 0 ? Scheme::Split : Scheme::Single;
    const std::uint64_t cache_blocks = config.scheme == Scheme::Split ? blocks / 2 : blocks;
    config.assoc = ways == 0 || ways > cache_blocks ? static_cast<std::uint32_t>(cache_blocks) : ways;
    config.size = blocks * config.block;
    if (config.scheme == Scheme::Split) {
      config.high_size = config.low_size = config.size / 2;
      config.high_policy = random() % 2 == 0 ? HighPolicy::Cache : HighPolicy::Retain;
      config.high_assoc = random() % 2 == 0 ? config.assoc : 1;
      config.split_level = static_cast<std::uint32_t>(random() % 6);
    }
    const std::size_t length = config.policy == ReplacementPolicy::Opt ? 1500 : 4000;
    const std::vector<Record> records =
        random_records(random, length, blocks * (2 + random() % 4), config.block, random() % 2 == 0);
    if (config.scheme == Scheme::Split && config.high_policy == HighPolicy::Retain) {
      std::vector<std::uint64_t> distinct;
      for (const Record& record : records) {
        if (record.tag < *config.split_level) distinct.push_back(block_of(record, config.block));
      }
      std::sort(distinct.begin(), distinct.end());
      distinct.erase(std::unique(distinct.begin(), distinct.end()), distinct.end());
      if (distinct.size() > config.high_size / config.block) config.high_policy = HighPolicy::Cache;
    }
    SCOPED_TRACE(::testing::Message() << "seed " << seed << " policy " << policy_name(config.policy)
                                      << " scheme " << scheme_name(config.scheme) << " size " << config.size
                                      << " block " << config.block << " ways " << config.assoc << " high "
                                      << high_policy_name(config.high_policy) << " " << config.high_assoc);
    const Counts expected = reference_counts(config, records);
    const ResultRow row = sweep_row(config, records);
    EXPECT_EQ(row.misses, expected.low_misses + expected.high_misses);
    if (config.scheme == Scheme::Split) {
      EXPECT_EQ(row.low_misses, expected.low_misses);
      EXPECT_EQ(row.high_misses, expected.high_misses);
      if (config.high_policy == HighPolicy::Retain) {
        EXPECT_EQ(row.high_loads.value_or(0), expected.high_loads);
      }
    }
    ++by_policy[config.policy];
    if (config.scheme == Scheme::Split) ++(config.high_policy == HighPolicy::Retain ? split_retained : split_cached);
  }
  for (const ReplacementPolicy policy : kPolicies) EXPECT_GE(by_policy[policy], 100u) << policy_name(policy);
  EXPECT_GE(split_retained, 25u);  // fewer: a retain set that cannot hold the levels becomes a cache
  EXPECT_GE(split_cached, 60u);
}

// The single caches of plru, srrip, brrip and drrip of 2 to 16 ways of one
// block size are simulated together by a policy grid: packed per-set state,
// 32-bit tags widened when a block number needs more, and consecutive
// fetches of one block in a set counted once (the filters). Over many
// seeded traces, with repeats, invalidations, block numbers past 2^32 from
// some point on and batches of any length (chunk edges inside runs), every
// member must count as the reference model does.
// With LRU and direct-mapped members too: their set stacks walk the lists
// the grid's filters keep (until an invalidation hands them over to caches
// of their own).
TEST(ReplacementPolicies, PolicyGridEqualsTheReferenceModelOverBatchesAndInvalidates) {
  constexpr ReplacementPolicy kGridPolicies[] = {ReplacementPolicy::Plru, ReplacementPolicy::Srrip,
                                                 ReplacementPolicy::Brrip, ReplacementPolicy::Drrip};
  std::size_t members = 0;
  std::size_t stacked = 0;
  std::size_t widened = 0;
  for (std::uint64_t seed = 1; seed <= 300; ++seed) {
    std::mt19937_64 random(seed);
    const std::uint32_t block = 4u << (random() % 4);  // 4 .. 32
    std::vector<Configuration> configs;
    for (int c = 0; c < 12; ++c) {
      Configuration config;
      config.block = block;
      config.policy = kGridPolicies[random() % std::size(kGridPolicies)];
      config.assoc = 2u << (random() % 4);  // 2 .. 16
      if (c >= 8) {  // answered by set stacks: LRU, or direct-mapped under any policy
        config.assoc = 1u << (random() % 5);  // 1 .. 16
        if (config.assoc > 1) config.policy = ReplacementPolicy::Lru;
      }
      config.size = std::uint64_t{config.assoc} * block << (random() % 10);  // 1 .. 512 sets
      if (std::find(configs.begin(), configs.end(), config) == configs.end()) configs.push_back(config);
    }
    // Members the set stacks answer, as simulated (duplicates dropped).
    stacked += static_cast<std::size_t>(std::count_if(configs.begin(), configs.end(), [](const Configuration& c) {
      return c.policy == ReplacementPolicy::Lru || c.assoc == 1;
    }));
    const std::uint64_t spread = 64 * (2 + random() % 12);
    std::vector<Record> records = random_records(random, 6000, spread, block, random() % 3 != 0);
    // Runs of one block, longer than the locality above makes them.
    std::vector<Record> repeated;
    for (const Record& record : records) {
      const std::size_t copies = random() % 4 == 0 ? 1 + random() % 4 : 1;
      for (std::size_t copy = 0; copy < copies; ++copy) repeated.push_back(record);
    }
    records = std::move(repeated);
    if (seed % 5 == 0) {  // block numbers of more than 32 bits after a while
      const std::size_t from = random() % records.size();
      for (std::size_t i = from; i < records.size(); ++i) records[i].address += (std::uint64_t{1} << 36) * block;
    }
    widened += std::any_of(records.begin(), records.end(), [&](const Record& record) {
      return record.type != AccessType::Invalidate && (record.address / block) >> 32 != 0;
    });
    TraceContext context;
    context.trace = "t";
    context.form = formats::RecordForm::Din;
    context.tags_are_levels = true;
    Sweep sweep(configs, context, false);
    if (seed % 2 == 0) sweep.set_parts(2);
    for (std::size_t at = 0; at < records.size();) {
      formats::RecordBatch batch;
      // Short batches put many chunk edges inside runs of one block.
      const std::size_t longest = seed % 3 == 0 ? 9000 : 40;
      const std::size_t length = std::min<std::size_t>(records.size() - at, 1 + random() % longest);
      batch.first_record = at;
      batch.records.assign(records.begin() + static_cast<std::ptrdiff_t>(at),
                           records.begin() + static_cast<std::ptrdiff_t>(at + length));
      sweep.feed(batch);
      at += length;
    }
    const TraceResult result = sweep.finish();
    const std::uint64_t fetches = static_cast<std::uint64_t>(std::count_if(
        records.begin(), records.end(), [](const Record& record) { return record.type != AccessType::Invalidate; }));
    ASSERT_EQ(result.rows.size(), configs.size());
    for (std::size_t c = 0; c < configs.size(); ++c) {
      const Configuration& config = configs[c];
      SCOPED_TRACE(::testing::Message() << "seed " << seed << " policy " << policy_name(config.policy) << " size "
                                        << config.size << " block " << block << " ways " << config.assoc);
      EXPECT_EQ(result.rows[c].refs, records.size());
      EXPECT_EQ(result.rows[c].fetches, fetches);
      EXPECT_EQ(result.rows[c].misses, reference_counts(config, records).low_misses);
      ++members;
    }
  }
  EXPECT_GT(members, 3000u);
  EXPECT_GE(stacked, 900u);  // of 1,200 drawn
  EXPECT_GE(widened, 55u);   // of 60 seeds whose block numbers grow past 32 bits
}

// Misses of a single cache of `size` bytes, `ways` ways, 8-byte blocks.
std::uint64_t single_misses(ReplacementPolicy policy, std::uint64_t size, std::uint32_t ways,
                            const std::vector<Record>& records) {
  Configuration config;
  config.size = size;
  config.block = 8;
  config.assoc = ways;
  config.policy = policy;
  return sweep_row(config, records).misses;
}

TEST(ReplacementPolicies, OptMissesNoMoreThanAnyPolicyWithTheSameSets) {
  for (std::uint64_t seed = 1; seed <= 40; ++seed) {
    std::mt19937_64 random(seed);
    const std::vector<Record> records = random_records(random, 20000, 700, 8, false);
    for (const std::uint32_t ways : {1u, 2u, 4u, 16u, 128u}) {
      const std::uint64_t opt = single_misses(ReplacementPolicy::Opt, 1024, ways, records);
      for (const ReplacementPolicy policy : kPolicies) {
        SCOPED_TRACE(::testing::Message() << "seed " << seed << " ways " << ways << " " << policy_name(policy));
        EXPECT_LE(opt, single_misses(policy, 1024, ways, records));
      }
      EXPECT_LE(opt, single_misses(ReplacementPolicy::Random, 1024, ways, records));
    }
  }
}

TEST(ReplacementPolicies, OptWithMoreCapacityNeverMissesMore) {
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    std::mt19937_64 random(seed);
    const std::vector<Record> records = random_records(random, 20000, 900, 8, seed % 2 == 0);
    for (const std::uint32_t ways : {1u, 4u, 0u}) {
      std::uint64_t previous = ~std::uint64_t{0};
      for (std::uint64_t size = 64; size <= 16384; size *= 2) {
        const std::uint32_t resolved = ways == 0 ? static_cast<std::uint32_t>(size / 8) : ways;
        const std::uint64_t misses = single_misses(ReplacementPolicy::Opt, size, resolved, records);
        EXPECT_LE(misses, previous) << "seed " << seed << " ways " << ways << " size " << size;
        previous = misses;
      }
    }
  }
}

TEST(ReplacementPolicies, PlruEqualsLruAtOneAndTwoWaysAndSrripAtOneWay) {
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    std::mt19937_64 random(seed);
    const std::vector<Record> records = random_records(random, 20000, 600, 8, seed % 2 == 0);
    for (const std::uint64_t size : {256u, 2048u}) {
      EXPECT_EQ(single_misses(ReplacementPolicy::Plru, size, 1, records),
                single_misses(ReplacementPolicy::Lru, size, 1, records));
      EXPECT_EQ(single_misses(ReplacementPolicy::Plru, size, 2, records),
                single_misses(ReplacementPolicy::Lru, size, 2, records));
      EXPECT_EQ(single_misses(ReplacementPolicy::Srrip, size, 1, records),
                single_misses(ReplacementPolicy::Lru, size, 1, records));
    }
  }
}

// At 4 ways the policies differ from LRU (and from each other) on these
// traces: the equalities above are not empty.
TEST(ReplacementPolicies, PoliciesDifferWhereTheyShould) {
  std::mt19937_64 random(5);
  const std::vector<Record> records = random_records(random, 50000, 2000, 8, false);
  std::vector<std::uint64_t> misses;
  for (const ReplacementPolicy policy : kPolicies) misses.push_back(single_misses(policy, 4096, 8, records));
  std::vector<std::uint64_t> distinct = misses;
  std::sort(distinct.begin(), distinct.end());
  distinct.erase(std::unique(distinct.begin(), distinct.end()), distinct.end());
  EXPECT_EQ(distinct.size(), misses.size());
}

// The opt configurations of one sweep share their kept fetches by block
// size and router; each still counts as when run alone.
TEST(ReplacementPolicies, OptConfigurationsOfOneSweepEqualEachRunAlone) {
  std::mt19937_64 random(17);
  const std::vector<Record> records = random_records(random, 30000, 900, 8, true);
  SweepOptions options;
  options.sizes = {512, 2048};
  options.blocks = {8, 16};
  options.assocs = {1, 4, 0};
  options.policies = {ReplacementPolicy::Opt, ReplacementPolicy::Lru};
  options.schemes = {Scheme::Single, Scheme::Split};
  options.split_levels = {3, 5};
  options.high_policies = {HighPolicy::Cache};
  const std::vector<Configuration> configs = expand_configurations(options);
  TraceContext context;
  context.trace = "t";
  context.form = formats::RecordForm::Din;
  context.tags_are_levels = true;
  Sweep sweep(configs, context, false);
  sweep.set_parts(2);  // the recorder and the others may be fed by other threads' parts
  formats::RecordBatch batch;
  batch.records = records;
  sweep.feed(batch);
  const TraceResult together = sweep.finish();
  ASSERT_EQ(together.rows.size(), configs.size());
  for (std::size_t c = 0; c < configs.size(); ++c) {
    const ResultRow alone = sweep_row(configs[c], records);
    EXPECT_EQ(together.rows[c].misses, alone.misses) << c;
    EXPECT_EQ(together.rows[c].high_misses, alone.high_misses) << c;
  }
}

TEST(ReplacementPolicies, PlruRefusesWaysThatAreNotAPowerOfTwo) {
  SweepOptions options;
  options.sizes = {8192};
  options.assocs = {3};
  options.policies = {ReplacementPolicy::Plru};
  try {
    expand_configurations(options);
    FAIL() << "no error";
  } catch (const base::UsageError& error) {
    EXPECT_NE(std::string(error.what()).find("power-of-two number of ways"), std::string::npos) << error.what();
  }
}

TEST(ReplacementPolicies, OptRefusesPerLevelAndPerFrameTablesAndPrefetching) {
  SweepOptions options;
  options.policies = {ReplacementPolicy::Opt};
  options.per_level = true;
  EXPECT_THROW(expand_configurations(options), base::UsageError);
  options.per_level = false;
  options.per_animation_frame = true;
  EXPECT_THROW(expand_configurations(options), base::UsageError);
  options.per_animation_frame = false;
  options.fetch = FetchPolicy::Always;
  EXPECT_THROW(expand_configurations(options), base::UsageError);
  options.policies = {ReplacementPolicy::Srrip};
  EXPECT_THROW(expand_configurations(options), base::UsageError);
}

}  // namespace
}  // namespace nodetrace::cachesim
