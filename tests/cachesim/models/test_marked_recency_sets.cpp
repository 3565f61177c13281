// The forms of a treelet prefetcher's LRU and FIFO sets
// (marked_recency_sets.hpp): with 4 and 8 ways fixed at compile time, the
// AVX2 demand and prefetch runs that processors with AVX2 take and the
// scalar ones, and the form for any number of ways, must miss, hit
// prefetched blocks and place prefetches alike on the same demand fetches,
// prefetch runs and invalidations. (The sweep's tests hold them to the
// reference model.)
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "models/marked_recency_sets.hpp"

namespace nodetrace::cachesim {
namespace {

// What one form answered, step by step.
struct Outcomes {
  std::vector<std::uint64_t> answers;  // per step: misses, placed prefetches, or 0
  std::uint64_t useful = 0;
};

// A random mix of demand runs (each miss prefetching the next few blocks, as
// the prefetcher does), prefetch runs and invalidations over few blocks, so
// that sets fill, blocks hit in every way and prefetched blocks are used,
// evicted and invalidated.
template <typename Sets>
Outcomes run_steps(Sets& sets, std::uint32_t ways, std::uint64_t seed) {
  std::mt19937_64 random(seed);
  const std::uint64_t blocks = 8 * 4 * ways;  // 8 sets, four blocks per way
  Outcomes outcomes;
  for (int step = 0; step < 4000; ++step) {
    const std::uint64_t kind = random() % 8;
    if (kind < 5) {
      std::vector<std::uint64_t> run(1 + random() % 16);
      for (std::uint64_t& block : run) block = random() % blocks;
      const std::uint64_t ahead = random() % 12;
      const std::uint64_t misses = sets.demand_run(
          run.size(), [&run](std::size_t i) { return run[i]; }, outcomes.useful,
          [&sets, ahead, &outcomes](std::uint64_t block) {
            if (ahead != 0) outcomes.answers.push_back(sets.prefetch_run(block + 1, block + ahead));
          });
      outcomes.answers.push_back(misses);
    } else if (kind < 7) {
      const std::uint64_t first = random() % blocks;
      outcomes.answers.push_back(sets.prefetch_run(first, first + random() % 40));
    } else {
      sets.invalidate(random() % blocks);
      outcomes.answers.push_back(0);
    }
  }
  return outcomes;
}

template <std::uint32_t Ways>
void expect_forms_agree(ReplacementPolicy policy) {
  const CacheGeometry geometry{8 * Ways * 8, 8, Ways, policy};
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    MarkedRecencySets<Ways> vector_form(geometry);
    MarkedRecencySets<Ways> scalar_form(geometry, false);
    MarkedRecencySets<> any_ways_form(geometry);
    const Outcomes vector_outcomes = run_steps(vector_form, Ways, seed);
    const Outcomes scalar_outcomes = run_steps(scalar_form, Ways, seed);
    const Outcomes any_ways_outcomes = run_steps(any_ways_form, Ways, seed);
    ASSERT_EQ(vector_outcomes.answers, scalar_outcomes.answers) << "seed " << seed;
    ASSERT_EQ(vector_outcomes.useful, scalar_outcomes.useful) << "seed " << seed;
    ASSERT_EQ(scalar_outcomes.answers, any_ways_outcomes.answers) << "seed " << seed;
    ASSERT_EQ(scalar_outcomes.useful, any_ways_outcomes.useful) << "seed " << seed;
    EXPECT_GT(vector_outcomes.useful, 0u);
  }
}

TEST(MarkedRecencySets, FourWaysAgreeInEveryFormUnderLru) { expect_forms_agree<4>(ReplacementPolicy::Lru); }
TEST(MarkedRecencySets, FourWaysAgreeInEveryFormUnderFifo) { expect_forms_agree<4>(ReplacementPolicy::Fifo); }
TEST(MarkedRecencySets, EightWaysAgreeInEveryFormUnderLru) { expect_forms_agree<8>(ReplacementPolicy::Lru); }
TEST(MarkedRecencySets, EightWaysAgreeInEveryFormUnderFifo) { expect_forms_agree<8>(ReplacementPolicy::Fifo); }

TEST(MarkedRecencySets, TheVectorFormIsTakenWhereTheProcessorHasAvx2) {
  const CacheGeometry geometry{256, 8, 4, ReplacementPolicy::Lru};
  EXPECT_EQ(MarkedRecencySets<4>(geometry).vector_runs(), cpu_has_avx2());
  EXPECT_EQ(MarkedRecencySets<8>(CacheGeometry{512, 8, 8, ReplacementPolicy::Lru}).vector_runs(),
            cpu_has_avx2());
  EXPECT_FALSE(MarkedRecencySets<4>(geometry, false).vector_runs());
  EXPECT_FALSE(MarkedRecencySets<2>(CacheGeometry{256, 8, 2, ReplacementPolicy::Lru}).vector_runs());
  EXPECT_FALSE(MarkedRecencySets<>(geometry).vector_runs());
}

}  // namespace
}  // namespace nodetrace::cachesim
