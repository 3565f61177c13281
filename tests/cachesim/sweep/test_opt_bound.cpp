// OPT as a true bound, whatever else a run lists: an opt cache listed after
// a cache of another policy of the same block size once counted MIN over no
// fetches (0 misses), and MIN once kept a block that an invalidation was
// about to remove. Beside those, the engine's rule for the address space's
// end: a reference past 2^64 - 1 continues at address 0 (as Dinero IV's past
// its 2^32 - 1 does), and block number 2^64 - 1, every cache model's free-way
// mark, is refused naming the record.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <random>
#include <set>
#include <vector>

#include "nodetrace/base/error.hpp"
#include "nodetrace/cachesim/sweep/sweep.hpp"

namespace nodetrace::cachesim {
namespace {

using formats::AccessType;
using formats::Record;

TraceResult run(const std::vector<Configuration>& configs, const std::vector<Record>& records,
                formats::RecordForm form, std::size_t parts = 1) {
  TraceContext context;
  context.trace = "t";
  context.source_name = "t.xdin";
  context.form = form;
  context.tags_are_levels = true;
  Sweep sweep(configs, context, false);
  sweep.set_parts(parts);
  formats::RecordBatch batch;
  batch.records = records;
  sweep.feed(batch);
  return sweep.finish();
}

Record reference(AccessType type, std::uint64_t address, std::uint32_t size) {
  Record record;
  record.type = type;
  record.address = address;
  record.size = size;
  return record;
}

ResultRow alone(const Configuration& config, const std::vector<Record>& records) {
  return run({config}, records, formats::RecordForm::Din).rows.at(0);
}

std::vector<Record> node_fetches(std::uint64_t seed, std::size_t count) {
  std::mt19937_64 random(seed);
  std::vector<Record> records(count);
  std::uint64_t at = 0;
  for (Record& record : records) {
    at = random() % 5 == 0 ? random() % 900 : (at + random() % 4) % 900;
    record.address = 8 * at;
    record.size = 4;
    record.tag = static_cast<formats::Tag>(at % 20);  // levels 0 and 1: 90 blocks
    record.type = random() % 40 == 0 ? AccessType::Invalidate : AccessType::Read;
  }
  return records;
}

// Distinct blocks of `block` bytes fetched: a cold cache misses each once.
std::uint64_t distinct_blocks(const std::vector<Record>& records, std::uint32_t block) {
  std::set<std::uint64_t> blocks;
  for (const Record& record : records) {
    if (record.type != AccessType::Invalidate) blocks.insert(record.address / block);
  }
  return blocks.size();
}

TEST(OptBound, OptListedAfterEveryOtherPolicyEqualsItsRunAlone) {
  const std::vector<Record> records = node_fetches(3, 20000);
  const std::vector<std::vector<ReplacementPolicy>> lists = {
      {ReplacementPolicy::Lru, ReplacementPolicy::Opt},
      {ReplacementPolicy::Fifo, ReplacementPolicy::Opt},
      {ReplacementPolicy::Random, ReplacementPolicy::Opt},
      {ReplacementPolicy::Lru, ReplacementPolicy::Srrip, ReplacementPolicy::Opt},
      {ReplacementPolicy::Lru, ReplacementPolicy::Plru, ReplacementPolicy::Srrip, ReplacementPolicy::Drrip,
       ReplacementPolicy::Opt},
  };
  for (const auto& policies : lists) {
    for (const std::size_t parts : {std::size_t{1}, std::size_t{2}}) {
      SweepOptions options;
      options.sizes = {2048, 4096};
      options.assocs = {1, 4, 0};
      options.policies = policies;
      options.schemes = {Scheme::Single, Scheme::Split};
      options.split_levels = {2};
      options.high_policies = {HighPolicy::Retain, HighPolicy::Cache};
      const std::vector<Configuration> configs = expand_configurations(options);
      const TraceResult together = run(configs, records, formats::RecordForm::Din, parts);
      ASSERT_EQ(together.rows.size(), configs.size());
      for (std::size_t c = 0; c < configs.size(); ++c) {
        if (configs[c].policy != ReplacementPolicy::Opt) continue;
        SCOPED_TRACE(::testing::Message() << "list of " << policies.size() << ", parts " << parts
                                          << ", configuration " << c);
        const ResultRow expected = alone(configs[c], records);
        EXPECT_EQ(together.rows[c].misses, expected.misses);
        EXPECT_EQ(together.rows[c].low_misses, expected.low_misses);
        EXPECT_EQ(together.rows[c].high_misses, expected.high_misses);
        if (configs[c].scheme == Scheme::Single) {
          EXPECT_GE(together.rows[c].misses, distinct_blocks(records, configs[c].block));
        }
      }
    }
  }
}

TEST(OptBound, ABlockInvalidatedBeforeItsNextUseCountsAsNeverUsedAgain) {
  // The trace: MIN used to keep block 0x10 for the fetch after its
  // invalidation and evict 0x8 instead, 5 misses where LRU has 4.
  const std::vector<Record> records = {
      reference(AccessType::Read, 0x10, 8),       reference(AccessType::Read, 0x0, 8),
      reference(AccessType::Read, 0x10, 8),       reference(AccessType::Read, 0x8, 8),
      reference(AccessType::Read, 0x10, 8),       reference(AccessType::Invalidate, 0x0, 8),
      reference(AccessType::Invalidate, 0x10, 8), reference(AccessType::Read, 0x0, 8),
      reference(AccessType::Read, 0x8, 8),
  };
  SweepOptions options;
  options.sizes = {16};
  options.assocs = {2};
  options.policies = {ReplacementPolicy::Opt, ReplacementPolicy::Lru};
  const TraceResult result = run(expand_configurations(options), records, formats::RecordForm::ExtendedDin);
  EXPECT_EQ(result.rows.at(0).misses, 4u);  // opt
  EXPECT_EQ(result.rows.at(1).misses, 4u);  // lru, as Dinero IV counts
}

// The fewest misses any choice of evictions (or bypasses) gives a fully
// associative cache of `ways` blocks on `events` (block numbers below 8,
// invalidations negative - 1), by trying every choice.
std::uint64_t exhaustive_optimum(const std::vector<int>& events, std::size_t at, unsigned resident,
                                 unsigned ways) {
  if (at == events.size()) return 0;
  const int event = events[at];
  if (event < 0) return exhaustive_optimum(events, at + 1, resident & ~(1u << (-event - 1)), ways);
  const unsigned bit = 1u << event;
  if (resident & bit) return exhaustive_optimum(events, at + 1, resident, ways);
  if (static_cast<unsigned>(std::popcount(resident)) < ways) {
    return 1 + exhaustive_optimum(events, at + 1, resident | bit, ways);
  }
  std::uint64_t best = exhaustive_optimum(events, at + 1, resident, ways);  // bypass
  for (unsigned victim = 0; victim < 8; ++victim) {
    if (resident & (1u << victim)) {
      best = std::min(best, exhaustive_optimum(events, at + 1, (resident & ~(1u << victim)) | bit, ways));
    }
  }
  return 1 + best;
}

TEST(OptBound, OptEqualsTheExhaustiveOptimumOnTracesWithInvalidations) {
  for (std::uint64_t seed = 1; seed <= 300; ++seed) {
    std::mt19937_64 random(seed);
    const unsigned universe = 3 + static_cast<unsigned>(seed % 5);
    std::vector<int> events(14);
    std::vector<Record> records;
    for (int& event : events) {
      const auto block = static_cast<int>(random() % universe);
      const bool invalidate = random() % 3 == 0;
      event = invalidate ? -block - 1 : block;
      records.push_back(reference(invalidate ? AccessType::Invalidate : AccessType::Read,
                                  8 * static_cast<std::uint64_t>(block), 8));
    }
    SweepOptions options;
    options.sizes = {16, 32};
    options.assocs = {0};
    options.policies = {ReplacementPolicy::Lru, ReplacementPolicy::Opt};
    const std::vector<Configuration> configs = expand_configurations(options);
    const TraceResult result = run(configs, records, formats::RecordForm::ExtendedDin);
    for (std::size_t c = 0; c < configs.size(); ++c) {
      if (configs[c].policy != ReplacementPolicy::Opt) continue;
      EXPECT_EQ(result.rows[c].misses, exhaustive_optimum(events, 0, 0, configs[c].assoc))
          << "seed " << seed << ", " << configs[c].assoc << " ways";
      EXPECT_LE(result.rows[c].misses, result.rows[c - 1].misses) << "seed " << seed << ": opt against lru";
    }
  }
}

TEST(AddressSpaceEnd, AReferencePastTheLastAddressContinuesAtAddressZero) {
  // 8 bytes from 2^64 - 7: Dinero IV's rule continues at 0, so blocks of 2
  // bytes are 0x7ffffffffffffffc .. 0x7fffffffffffffff and block 0 (5), of
  // 8 bytes the last block and block 0 (2); the fetch of address 0 after it
  // hits in a cache that kept block 0.
  const std::vector<Record> records = {
      reference(AccessType::Read, 0xfffffffffffffff9, 8),
      reference(AccessType::Read, 0x0, 1),
  };
  SweepOptions options;
  options.sizes = {64};
  options.blocks = {2, 8};
  options.assocs = {0, 1};
  options.policies = {ReplacementPolicy::Lru, ReplacementPolicy::Srrip};
  const std::vector<Configuration> configs = expand_configurations(options);
  const TraceResult result = run(configs, records, formats::RecordForm::ExtendedDin);
  for (std::size_t c = 0; c < configs.size(); ++c) {
    SCOPED_TRACE(::testing::Message() << "block " << configs[c].block << ", ways " << configs[c].assoc << ", "
                                      << policy_name(configs[c].policy));
    const std::uint64_t first_reference = configs[c].block == 2 ? 5 : 2;
    EXPECT_EQ(result.rows[c].fetches, first_reference + 1);
    EXPECT_EQ(result.rows[c].misses, first_reference);
  }
}

TEST(AddressSpaceEnd, TheLastOneByteBlockIsRefusedNamingTheRecord) {
  std::vector<Record> records(5, reference(AccessType::Read, 0x40, 4));
  records[3] = reference(AccessType::Read, 0xffffffffffffffff, 1);
  SweepOptions options;
  options.sizes = {64};
  options.blocks = {1};
  options.assocs = {0};
  try {
    run(expand_configurations(options), records, formats::RecordForm::ExtendedDin);
    FAIL() << "block number 2^64 - 1 was simulated";
  } catch (const base::FormatError& error) {
    EXPECT_EQ(std::string(error.what()),
              "t.xdin: record 4: address 0xffffffffffffffff of 1 bytes reaches address 0xffffffffffffffff, whose "
              "1-byte block (block number 2^64 - 1) is the caches' mark of a free way and is not simulated; use "
              "--block 2 or more");
  }
  // With blocks of 2 bytes the same record is block 2^63 - 1, simulated.
  options.blocks = {2};
  EXPECT_EQ(run(expand_configurations(options), records, formats::RecordForm::ExtendedDin).rows.at(0).misses, 3u);
}

}  // namespace
}  // namespace nodetrace::cachesim
