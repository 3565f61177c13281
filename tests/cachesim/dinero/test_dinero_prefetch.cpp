// Dinero IV's fetch policies in the engine: each one's prefetches on small
// traces worked out by hand (and checked against d4-7), the abort
// percentage, and the whole output against the real Dinero IV for every
// policy when one is at hand.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <vector>

#include "nodetrace/cachesim/dinero/command_line.hpp"
#include "nodetrace/cachesim/dinero/engine.hpp"
#include "test_support.hpp"

namespace nodetrace::cachesim {
namespace {

constexpr int kRead = 0;

formats::Record read(std::uint64_t address) {
  return formats::Record{address, 4, formats::AccessType::Read, formats::TraversalUnit{}, formats::kTagNone};
}

// A 64-byte direct-mapped unified cache of 16-byte blocks.
Stats run(FetchPolicy fetch, std::vector<formats::Record> records, std::uint32_t sub_block = 0,
          std::uint32_t abort = 0) {
  CacheConfig cache;
  cache.size = 64;
  cache.block_size = 16;
  cache.sub_block_size = sub_block;
  cache.fetch = fetch;
  cache.prefetch_abort = abort;
  Hierarchy h(single_level(cache));
  for (const auto& r : records) h.access(r);
  h.finish();
  return h.stats(1, CacheKind::Unified);
}

TEST(DineroPrefetch, AlwaysPrefetchesTheNextSubBlockOnEveryRead) {
  const Stats s = run(FetchPolicy::Always, {read(0x0), read(0x10), read(0x20)});
  EXPECT_EQ(s.fetches[kRead], 3u);
  EXPECT_EQ(s.misses[kRead], 1u);  // 0x10 and 0x20 were prefetched
  EXPECT_EQ(s.prefetch.fetches[kRead], 3u);
  EXPECT_EQ(s.prefetch.misses[kRead], 3u);
  EXPECT_EQ(s.bytes_from_memory, 64u);  // one demand and three prefetch fills
}

TEST(DineroPrefetch, MissPrefetchesOnlyOnAMiss) {
  const Stats s = run(FetchPolicy::Miss, {read(0x0), read(0x10), read(0x20)});
  EXPECT_EQ(s.misses[kRead], 2u);
  EXPECT_EQ(s.prefetch.fetches[kRead], 2u);
  EXPECT_EQ(s.prefetch.misses[kRead], 2u);
}

TEST(DineroPrefetch, TaggedPrefetchesOnTheFirstDemandUseOfAPrefetchedBlock) {
  // 0x10 the second time was referenced already: no prefetch.
  const Stats s = run(FetchPolicy::Tagged, {read(0x0), read(0x10), read(0x20), read(0x10)});
  EXPECT_EQ(s.fetches[kRead], 4u);
  EXPECT_EQ(s.misses[kRead], 1u);
  EXPECT_EQ(s.prefetch.fetches[kRead], 3u);
}

TEST(DineroPrefetch, LoadForwardNeverPrefetchesIntoTheNextBlock) {
  const Stats s = run(FetchPolicy::LoadForward, {read(0x0), read(0xc)}, 4);
  EXPECT_EQ(s.misses[kRead], 2u);
  EXPECT_EQ(s.prefetch.fetches[kRead], 1u);  // only after 0x0, of 0x4
  EXPECT_EQ(s.prefetch.misses[kRead], 1u);
  EXPECT_EQ(s.prefetch.block_misses[kRead], 0u);
}

TEST(DineroPrefetch, SubBlockWrapsRoundWithinTheBlock) {
  // After 0xc the prefetch is of 0x0 (not 0x10), so the read of 0x0 hits.
  const Stats s = run(FetchPolicy::SubBlock, {read(0xc), read(0x0)}, 4);
  EXPECT_EQ(s.misses[kRead], 1u);
  EXPECT_EQ(s.prefetch.fetches[kRead], 2u);
  EXPECT_EQ(s.prefetch.misses[kRead], 2u);
  EXPECT_EQ(s.block_misses[kRead], 1u);
}

TEST(DineroPrefetch, AbortHundredPercentThrowsEveryPrefetchAway) {
  const Stats s = run(FetchPolicy::Always, {read(0x0), read(0x10), read(0x20)}, 0, 100);
  EXPECT_EQ(s.misses[kRead], 3u);
  EXPECT_EQ(s.prefetch.fetches[kRead], 0u);
}

TEST(DineroPrefetch, EveryPolicyPrintsWhatTheRealDineroIVPrints) {
  NODETRACE_SHARED_OR_SKIP(shared);
  NODETRACE_DINERO_OR_SKIP(dinero);
  const auto trace = shared / "dinero-golden" / "mm32.din.zst";
  for (const char* fetch : {"a", "m", "t", "l", "s"}) {
    // Split L1 with sub-blocks and ccc, a random-replacement L2 that throws
    // a third of its prefetches away: every prefetch row and the random draws.
    const std::string args = fmt::format(
        "-informat d -l1-isize 1k -l1-ibsize 16 -l1-isbsize 4 -l1-ifetch {0} -l1-dsize 1k -l1-dbsize 16 "
        "-l1-dsbsize 8 -l1-dfetch {0} -l1-dassoc 2 -l1-dccc -l2-usize 8k -l2-ubsize 32 -l2-ufetch {0} "
        "-l2-upfabort 30 -l2-urepl r -l2-uccc",
        fetch);
    const std::string input = "zstd -dc '" + trace.string() + "' | ";
    const auto real = testing::run_command(input + "'" + dinero.string() + "' " + args);
    const auto ours = testing::run_command(input + "'" + testing::program("cachesim").string() + "' dinero " + args);
    ASSERT_EQ(real.exit_code, 0) << real.err;
    ASSERT_EQ(ours.exit_code, 0) << ours.err;
    EXPECT_NE(ours.out.find(" PFB comp misses\t"), std::string::npos);
    EXPECT_TRUE(ours.out == real.out) << "-lN-Tfetch " << fetch;
  }
}

}  // namespace
}  // namespace nodetrace::cachesim
