// The treelet prefetcher finds a missed block's treelet end in a per-block
// table when the map allows one, and searches the map when it does not (a
// map spanning more than 2^22 blocks, or a treelet of 2^16 blocks or more):
// the two must prefetch the same blocks. The harness's random maps always
// take the table, so the search is held to it here.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "models/marked_recency_sets.hpp"
#include "models/treelet_prefetcher.hpp"

namespace nodetrace::cachesim {
namespace {

constexpr std::uint64_t kBlock = 8;

// Treelets of 1 to 40 blocks, some with a gap before them, over about 4,000 blocks.
formats::TreeletMap short_treelets(std::mt19937_64& random) {
  formats::TreeletMap map;
  std::uint64_t at = 0;
  while (at < 4000 * kBlock) {
    at += (random() % 4 == 0 ? random() % 5 : 0) * kBlock;
    const std::uint64_t bytes = (1 + random() % 40) * kBlock - random() % kBlock;
    map.treelets.push_back({at, bytes});
    at += bytes + random() % kBlock;
  }
  return map;
}

struct Answer {
  std::vector<std::uint64_t> misses;  // per batch of records
  PrefetchCounts counts;
  bool operator==(const Answer& other) const {
    return misses == other.misses && counts.prefetches == other.counts.prefetches &&
           counts.useful == other.counts.useful;
  }
};

template <typename MarkedCache>
Answer run(const CacheGeometry& geometry, std::uint64_t limit, const formats::TreeletMap& map,
           const std::vector<formats::Record>& records) {
  TreeletPrefetcher<MarkedCache> prefetcher(geometry, limit);
  prefetcher.begin_treelets(&map);
  Answer answer;
  for (std::size_t first = 0; first < records.size(); first += 100) {
    const std::size_t count = std::min<std::size_t>(100, records.size() - first);
    if (first % 200 == 0) {
      answer.misses.push_back(prefetcher.access_blocks_of(records.data() + first, count, 3));
    } else {
      std::uint64_t misses = 0;
      for (std::size_t i = first; i < first + count; ++i) misses += prefetcher.access(records[i].address >> 3);
      answer.misses.push_back(misses);
    }
  }
  answer.counts = prefetcher.prefetch_counts();
  return answer;
}

template <typename MarkedCache>
void expect_search_equals_table(const CacheGeometry& geometry) {
  for (std::uint64_t seed = 1; seed <= 10; ++seed) {
    std::mt19937_64 random(seed);
    const formats::TreeletMap tabled = short_treelets(random);
    // Each takes the search for every miss, though only the short treelets are met.
    formats::TreeletMap long_treelet = tabled, wide_span = tabled;
    long_treelet.treelets.push_back({8000 * kBlock, ((std::uint64_t{1} << 16) + 1) * kBlock});
    wide_span.treelets.push_back({(std::uint64_t{1} << 23) * kBlock, kBlock});
    std::vector<formats::Record> records(3000);
    for (formats::Record& r : records) r.address = random() % (4100 * kBlock);
    for (const std::uint64_t limit : {std::uint64_t{0}, std::uint64_t{64}}) {
      const Answer table = run<MarkedCache>(geometry, limit, tabled, records);
      ASSERT_GT(table.counts.prefetches, 0u);
      EXPECT_TRUE(run<MarkedCache>(geometry, limit, long_treelet, records) == table) << seed << " " << limit;
      EXPECT_TRUE(run<MarkedCache>(geometry, limit, wide_span, records) == table) << seed << " " << limit;
    }
  }
}

TEST(TreeletPrefetcher, SearchingTheMapPrefetchesWhatTheTableDoesDirectMapped) {
  expect_search_equals_table<SlotMarkedCache<DirectMappedSlots>>({1024, kBlock, 1, ReplacementPolicy::Lru});
}

TEST(TreeletPrefetcher, SearchingTheMapPrefetchesWhatTheTableDoesFourWays) {
  expect_search_equals_table<MarkedRecencySets<4>>({1024, kBlock, 4, ReplacementPolicy::Lru});
}

}  // namespace
}  // namespace nodetrace::cachesim
