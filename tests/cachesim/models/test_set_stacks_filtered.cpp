// SetStacks::access_records_filtered: set stacks that walk lists another
// filter kept (a policy grid's) count exactly as the walk over every record.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "nodetrace/cachesim/models/set_stacks.hpp"
#include "nodetrace/formats/record/record.hpp"

namespace nodetrace::cachesim {
namespace {

using formats::Record;

// The fetches of `blocks` whose block is not the last one fetched in its
// set of 2^log2_sets sets (`last`: per set, over every batch so far), and
// some that are (as a grid keeps at the start of its chunks).
struct OnTopFilter {
  unsigned log2_sets;
  std::vector<std::uint64_t> last;
  std::vector<std::uint64_t> kept;

  explicit OnTopFilter(unsigned log2) : log2_sets(log2), last(std::size_t{1} << log2, ~std::uint64_t{0}) {}

  SetStacks::Filtered filter(const std::vector<std::uint64_t>& blocks, std::mt19937_64& random) {
    kept.clear();
    for (const std::uint64_t block : blocks) {
      std::uint64_t& in_set = last[block & (last.size() - 1)];
      if (in_set != block || random() % 8 == 0) kept.push_back(block);
      in_set = block;
    }
    return {log2_sets, kept.data(), kept.size()};
  }
};

// Blocks with locality and runs of one block; after `wide_from`, some need
// more than 32 bits (and alias narrow ones in their low bits).
std::vector<std::uint64_t> blocks_with_runs(std::mt19937_64& random, std::size_t count, std::size_t wide_from) {
  std::vector<std::uint64_t> blocks;
  std::uint64_t at = 0;
  while (blocks.size() < count) {
    at = random() % 5 == 0 ? random() % 4096 : (at + random() % 7) % 4096;
    const std::uint64_t block = blocks.size() >= wide_from && random() % 3 == 0 ? at + (std::uint64_t{1} << 32) : at;
    for (std::size_t copies = 1 + (random() % 3 == 0 ? random() % 3 : 0); copies > 0; --copies) blocks.push_back(block);
  }
  return blocks;
}

// Filters at set counts among, between, below and above the stacks' own.
TEST(SetStacksFiltered, WalkingKeptListsEqualsWalkingEveryRecord) {
  const std::vector<SetStacks::Level> levels{{1, 8}, {3, 4}, {4, 1}, {6, 8}, {7, 2}, {9, 16}, {10, 3}};
  const std::vector<std::vector<unsigned>> filter_sets{{0, 3, 6}, {3, 5, 8}, {1, 2, 4, 6, 7, 9, 10}, {11}, {2}};
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    std::mt19937_64 random(seed);
    const std::vector<unsigned>& sets = filter_sets[seed % filter_sets.size()];
    const std::size_t count = 20000;
    const std::vector<std::uint64_t> blocks = blocks_with_runs(random, count, seed % 2 == 0 ? count / 2 : count);
    SetStacks walked(levels);
    SetStacks filtered(levels);
    std::vector<OnTopFilter> filters(sets.begin(), sets.end());
    for (std::size_t begin = 0; begin < count;) {
      const std::size_t length = std::min<std::size_t>(1 + random() % 3000, count - begin);
      const std::vector<std::uint64_t> batch(blocks.begin() + static_cast<std::ptrdiff_t>(begin),
                                             blocks.begin() + static_cast<std::ptrdiff_t>(begin + length));
      std::vector<Record> records;
      bool fit = true;
      for (const std::uint64_t block : batch) {
        records.push_back({.address = (block << 3) + random() % 8});
        fit = fit && block < 0xFFFFFFFF;
      }
      std::vector<SetStacks::Filtered> lists;
      for (OnTopFilter& filter : filters) lists.push_back(filter.filter(batch, random));
      walked.access_records(records.data(), records.size(), 3);
      filtered.access_records_filtered(records.data(), records.size(), 3, lists, fit);
      begin += length;
    }
    EXPECT_EQ(filtered.fetches(), walked.fetches());
    for (const SetStacks::Level& level : levels) {
      for (std::uint32_t ways = 1; ways <= level.depth; ++ways) {
        EXPECT_EQ(filtered.misses(level.log2_sets, ways), walked.misses(level.log2_sets, ways))
            << "seed " << seed << ", 2^" << level.log2_sets << " sets, " << ways << " ways";
      }
      for (std::uint64_t set = 0; set < (std::uint64_t{1} << level.log2_sets); ++set) {
        ASSERT_EQ(filtered.ways_of(level.log2_sets, set, level.depth), walked.ways_of(level.log2_sets, set, level.depth))
            << "seed " << seed << ", 2^" << level.log2_sets << " sets, set " << set;
      }
    }
  }
}

}  // namespace
}  // namespace nodetrace::cachesim
