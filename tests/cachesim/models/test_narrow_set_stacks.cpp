// The forms of the narrow 8-place set stacks (narrow_set_stack_run.hpp):
// the 16-byte-vector form and the AVX2 form that processors with AVX2 run
// must keep the same stacks, pass on the same fetches and count the same
// places as a plain move-to-front list.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

#include "models/narrow_set_stack_run.hpp"

namespace nodetrace::cachesim {
namespace {

constexpr unsigned kDepth = 8;

struct StackRun {
  std::vector<std::uint32_t> stacks;
  std::vector<std::uint64_t> passed;
  std::uint64_t deeper[kDepth + 1] = {};
};

// A move-to-front list per set, written plainly.
StackRun plain_run(const std::vector<std::uint64_t>& blocks, std::uint64_t mask) {
  StackRun run;
  run.stacks.assign((mask + 1) * kDepth, kNarrowEmpty);
  for (const std::uint64_t block : blocks) {
    std::uint32_t* const stack = run.stacks.data() + (block & mask) * kDepth;
    const auto narrow = static_cast<std::uint32_t>(block);
    const unsigned place = static_cast<unsigned>(std::find(stack, stack + kDepth, narrow) - stack);
    std::copy_backward(stack, stack + std::min(place, kDepth - 1), stack + std::min(place, kDepth - 1) + 1);
    stack[0] = narrow;
    if (place != 0) {
      ++run.deeper[place];
      run.passed.push_back(block);
    }
  }
  return run;
}

template <typename Runner>
StackRun vector_run(const std::vector<std::uint64_t>& blocks, std::uint64_t mask, Runner runner) {
  StackRun run;
  run.stacks.assign((mask + 1) * kDepth, kNarrowEmpty);
  run.passed.resize(blocks.size());
  // In uneven batches, the stacks carried from one to the next.
  std::mt19937_64 random(mask);
  std::size_t passed = 0;
  for (std::size_t at = 0; at < blocks.size();) {
    const std::size_t length = std::min<std::size_t>(blocks.size() - at, 1 + random() % 700);
    passed += runner(run.stacks.data(), mask, blocks.data() + at, length, run.passed.data() + passed, run.deeper);
    at += length;
  }
  run.passed.resize(passed);
  return run;
}

void expect_same(const StackRun& run, const StackRun& plain) {
  EXPECT_EQ(run.stacks, plain.stacks);
  EXPECT_EQ(run.passed, plain.passed);
  for (unsigned place = 1; place <= kDepth; ++place) EXPECT_EQ(run.deeper[place], plain.deeper[place]) << place;
}

// Blocks that repeat at every depth: a few hundred blocks over few sets,
// including the largest block a narrow stack holds (2^32 - 2).
std::vector<std::uint64_t> repeating_blocks(std::uint64_t seed) {
  std::mt19937_64 random(seed);
  std::vector<std::uint64_t> blocks;
  for (int i = 0; i < 20000; ++i) {
    const std::uint64_t block = random() % 7 == 0 ? 0xFFFFFFFEull - random() % 64 : random() % (64 + seed * 40);
    blocks.push_back(block);
  }
  return blocks;
}

TEST(NarrowSetStacks, SixteenByteFormEqualsAMoveToFrontList) {
  for (std::uint64_t seed = 1; seed <= 12; ++seed) {
    const std::vector<std::uint64_t> blocks = repeating_blocks(seed);
    for (const std::uint64_t mask : {0ull, 3ull, 15ull}) {
      SCOPED_TRACE(::testing::Message() << "seed " << seed << " sets " << mask + 1);
      expect_same(vector_run(blocks, mask, run_narrow_set_stacks<kDepth, const std::uint64_t*>), plain_run(blocks, mask));
    }
  }
}

TEST(NarrowSetStacks, Avx2FormEqualsAMoveToFrontList) {
#if defined(NODETRACE_NARROW_STACKS_AVX2)
  if (!__builtin_cpu_supports("avx2")) GTEST_SKIP() << "this processor has no AVX2";
  for (std::uint64_t seed = 1; seed <= 12; ++seed) {
    const std::vector<std::uint64_t> blocks = repeating_blocks(seed);
    for (const std::uint64_t mask : {0ull, 3ull, 15ull}) {
      SCOPED_TRACE(::testing::Message() << "seed " << seed << " sets " << mask + 1);
      expect_same(vector_run(blocks, mask, run_narrow_set_stacks_avx2<const std::uint64_t*>), plain_run(blocks, mask));
    }
  }
#else
  GTEST_SKIP() << "no AVX2 form on this architecture";
#endif
}

}  // namespace
}  // namespace nodetrace::cachesim
