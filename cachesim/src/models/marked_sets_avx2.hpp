// Internal: MarkedRecencySets' runs of demand fetches and of prefetches
// (marked_recency_sets.hpp) on a processor with AVX2 and BMI2, for sets of
// 4 and 8 ways: a set's blocks are one or two 32-byte vectors, compared
// with the block at once and moved one way older by a lane permutation,
// where the scalar loops compare and move them one by one. Measured in
// docs/PERFORMANCE.md, "The treelet prefetcher".
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#define NODETRACE_MARKED_SETS_AVX2 1
#endif

namespace nodetrace::cachesim {

#if defined(NODETRACE_MARKED_SETS_AVX2)
inline bool cpu_has_avx2() {
  return __builtin_cpu_supports("avx2") != 0 && __builtin_cpu_supports("bmi") != 0 &&
         __builtin_cpu_supports("bmi2") != 0;
}

namespace detail {
// Lanes [0, 0, 1, 2] of a vector of four ways: each moved one way older, lane 0 to take the block.
constexpr int kOneOlder = 0x90;

// The set's `Ways` blocks, newest first, with `block` newest and the
// lanes below `moving` moved one way older (the oldest of them leaves).
template <std::uint32_t Ways>
[[gnu::always_inline]] __attribute__((target("avx2"))) inline void push_newest(__m256i* ways, __m256i newer,
                                                                             __m256i older, __m256i block,
                                                                             __m256i moving_newer,
                                                                             __m256i moving_older) {
  if constexpr (Ways == 8) {
    // Way 3 crosses into the older vector's first lane.
    const __m256i carried = _mm256_permute4x64_epi64(newer, 0xff);
    const __m256i pushed = _mm256_blend_epi32(_mm256_permute4x64_epi64(older, kOneOlder), carried, 0x03);
    _mm256_storeu_si256(ways + 1, _mm256_blendv_epi8(older, pushed, moving_older));
  }
  const __m256i pushed = _mm256_blend_epi32(_mm256_permute4x64_epi64(newer, kOneOlder), block, 0x03);
  _mm256_storeu_si256(ways, _mm256_blendv_epi8(newer, pushed, moving_newer));
}

// Per way count from 0 to 8: all ones in the 64-bit lanes below it (lanes 0-3, then 4-7).
alignas(32) inline constexpr std::int64_t kLanesBelow[9][8] = {
    {0, 0, 0, 0, 0, 0, 0, 0},     {-1, 0, 0, 0, 0, 0, 0, 0},     {-1, -1, 0, 0, 0, 0, 0, 0},
    {-1, -1, -1, 0, 0, 0, 0, 0},  {-1, -1, -1, -1, 0, 0, 0, 0},  {-1, -1, -1, -1, -1, 0, 0, 0},
    {-1, -1, -1, -1, -1, -1, 0, 0}, {-1, -1, -1, -1, -1, -1, -1, 0}, {-1, -1, -1, -1, -1, -1, -1, -1}};
}  // namespace detail

// Places each block from `first` to `last` newest in its set of `Ways`
// (tags: the sets' blocks, newest first; marks: bit w per set for way w),
// marked, unless it is resident; returns how many were placed.
template <std::uint32_t Ways>
__attribute__((target("avx2,bmi,bmi2"))) std::uint64_t prefetch_run_avx2(std::uint64_t* tags, std::uint32_t* marks,
                                                                         std::uint64_t set_mask, std::uint64_t first,
                                                                         std::uint64_t last) {
  static_assert(Ways == 4 || Ways == 8);
  constexpr std::uint32_t kAllWays = (std::uint32_t{1} << Ways) - 1;
  const __m256i all = _mm256_set1_epi64x(-1);
  const __m256i one = _mm256_set1_epi64x(1);
  __m256i wanted = _mm256_set1_epi64x(static_cast<long long>(first));
  std::uint64_t placed = 0;
  for (std::uint64_t block = first;; ++block) {
    const std::uint64_t set = block & set_mask;
    auto* const ways = reinterpret_cast<__m256i*>(tags + set * Ways);
    const __m256i newer = _mm256_loadu_si256(ways);
    __m256i found = _mm256_cmpeq_epi64(newer, wanted);
    __m256i older{};
    if constexpr (Ways == 8) {
      older = _mm256_loadu_si256(ways + 1);
      found = _mm256_or_si256(found, _mm256_cmpeq_epi64(older, wanted));
    }
    if (_mm256_testz_si256(found, found) != 0) {
      detail::push_newest<Ways>(ways, newer, older, wanted, all, all);
      marks[set] = ((marks[set] << 1) | 1) & kAllWays;
      ++placed;
    }
    if (block == last) return placed;
    wanted = _mm256_add_epi64(wanted, one);
  }
}

// Demand fetches of `count` blocks (block_at(i) the i-th) in sets of `Ways`
// under LRU (`Lru`) or FIFO, as MarkedRecencySets::demand_run: the useful
// hits added to `useful`, on_miss(block) called after each miss, the
// misses returned. No branch on where the block is (a branch that the
// processor mispredicts for about a third of the fetches): the way found,
// `Ways` when absent, chooses the lanes that move and the mark taken.
template <std::uint32_t Ways, bool Lru, typename BlockAt, typename OnMiss>
__attribute__((target("avx2,bmi,bmi2"))) std::uint64_t demand_run_avx2(std::uint64_t* tags, std::uint32_t* marks,
                                                                       std::uint64_t set_mask, std::size_t count,
                                                                       BlockAt block_at, std::uint64_t& useful,
                                                                       OnMiss on_miss) {
  static_assert(Ways == 4 || Ways == 8);
  constexpr std::uint32_t kAllWays = (std::uint32_t{1} << Ways) - 1;
  std::uint64_t misses = 0;
  std::uint64_t used = 0;
  for (std::size_t i = 0; i < count; ++i) {
    const std::uint64_t block = block_at(i);
    const std::uint64_t set = block & set_mask;
    if (tags[set * Ways] == block) {
      // The newest way (most fetches): its mark taken, nothing moves. A
      // branch on the mark would mispredict for about one in three.
      used += marks[set] & 1;
      marks[set] &= ~std::uint32_t{1};
      continue;
    }
    auto* const ways = reinterpret_cast<__m256i*>(tags + set * Ways);
    const __m256i wanted = _mm256_set1_epi64x(static_cast<long long>(block));
    const __m256i newer = _mm256_loadu_si256(ways);
    auto found = static_cast<std::uint32_t>(_mm256_movemask_pd(_mm256_castsi256_pd(_mm256_cmpeq_epi64(newer, wanted))));
    __m256i older{};
    if constexpr (Ways == 8) {
      older = _mm256_loadu_si256(ways + 1);
      found |= static_cast<std::uint32_t>(_mm256_movemask_pd(_mm256_castsi256_pd(_mm256_cmpeq_epi64(older, wanted))))
               << 4;
    }
    const auto way = static_cast<std::uint32_t>(std::countr_zero(found | (std::uint32_t{1} << Ways)));
    const bool miss = way == Ways;
    // The ways that move one older, the block coming in newest: under LRU
    // those up to the way found, under FIFO all on a miss and none on a hit.
    const std::uint32_t moving = miss ? Ways : (Lru ? way + 1 : 0);
    const auto* const lanes = reinterpret_cast<const __m256i*>(detail::kLanesBelow[moving]);
    detail::push_newest<Ways>(ways, newer, older, wanted, _mm256_load_si256(lanes), _mm256_load_si256(lanes + 1));
    // The way's mark is taken (bit Ways, a miss's, is always 0); the marks move with their blocks.
    const std::uint32_t mark = marks[set];
    used += (mark >> way) & 1;
    if constexpr (Lru) {
      // The marks of the ways that move go one way older (a miss's drops the oldest).
      const std::uint32_t moved = (std::uint32_t{1} << moving) - 1;
      marks[set] = (mark & ~moved) | ((mark << 1) & moved);
    } else {
      marks[set] = miss ? (mark << 1) & kAllWays : mark & ~(std::uint32_t{1} << way);
    }
    if (miss) {
      ++misses;
      on_miss(block);
    }
  }
  useful += used;
  return misses;
}
#else
inline bool cpu_has_avx2() { return false; }
#endif

}  // namespace nodetrace::cachesim
