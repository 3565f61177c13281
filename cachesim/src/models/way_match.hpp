// Internal: which ways of a set hold a tag, found by comparing the set's tags
// at once in 16-byte vectors (GCC and Clang vector extensions: SSE2 on
// x86-64, NEON on arm64; on x86-64, 32-bit tags' comparisons are gathered
// by SSE2's movemask, one instruction where the generic fold takes four).
// The answer is a bit mask, bit w for way w, so the caller takes the lowest
// way with countr_zero.
#pragma once

#include <bit>
#include <cstdint>
#include <cstring>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace nodetrace::cachesim {

// Bit w set when tags[w] == tag, for `kWays` tags (a power of two, at most 32).
template <unsigned kWays, typename Tag>
inline std::uint32_t match_ways(const Tag* tags, Tag tag) {
  static_assert(sizeof(Tag) == 4 || sizeof(Tag) == 8);
  constexpr unsigned kLanes = 16 / sizeof(Tag);
  if constexpr (kWays < kLanes) {
    std::uint32_t mask = 0;
    for (unsigned way = 0; way < kWays; ++way) mask |= static_cast<std::uint32_t>(tags[way] == tag) << way;
    return mask;
  } else {
#if defined(__SSE2__)
    if constexpr (sizeof(Tag) == 4) {
      // One instruction gathers a vector's four comparisons.
      const __m128i wanted = _mm_set1_epi32(static_cast<int>(tag));
      std::uint32_t mask = 0;
      for (unsigned first = 0; first < kWays; first += kLanes) {
        const __m128i ways = _mm_loadu_si128(reinterpret_cast<const __m128i*>(tags + first));
        mask |= static_cast<std::uint32_t>(_mm_movemask_ps(_mm_castsi128_ps(_mm_cmpeq_epi32(ways, wanted)))) << first;
      }
      return mask;
    }
#endif
    using Vector [[gnu::vector_size(16)]] = Tag;
    // Each lane's weight is its way's bit: the matches ORed together are the mask.
    Vector weights;
    for (unsigned lane = 0; lane < kLanes; ++lane) weights[lane] = Tag{1} << lane;
    Vector matched{};
    for (unsigned first = 0; first < kWays; first += kLanes) {
      Vector ways;
      std::memcpy(&ways, tags + first, sizeof ways);  // any alignment
      matched |= (ways == tag) & (weights << first);
    }
    // Fold the lanes into one integer.
    if constexpr (sizeof(Tag) == 8) {
      return static_cast<std::uint32_t>(matched[0] | matched[1]);
    } else {
      std::uint64_t halves[2];
      std::memcpy(halves, &matched, sizeof halves);
      const std::uint64_t pairs = halves[0] | halves[1];
      return static_cast<std::uint32_t>(pairs | (pairs >> 32));
    }
  }
}

}  // namespace nodetrace::cachesim
