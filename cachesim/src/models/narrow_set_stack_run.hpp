// Internal: narrow set stacks, the fast form of one set count's LRU stacks
// (SetStacks, set_stacks.hpp) while every block seen fits in 32 bits: the
// same stacks (blocks most recent first) with 32-bit blocks. Measured on a
// rendered trace, a fetch is bound by the instructions it takes, and
// 32-bit lanes halve them: 8 places are two 16-byte vectors that baseline
// SSE2 compares lane by lane (its 32-bit equality; 64-bit equality needs
// SSE4.1), and a whole-vector byte shift moves them down.
//
// Exactness: a narrow block is the block itself, so it needs every block
// to be below kNarrowEmpty; SetStacks widens the stacks (each narrow block
// to 64 bits, kNarrowEmpty to kEmpty) before the first block that is not.
#pragma once

#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#define NODETRACE_NARROW_STACKS_AVX2 1
#endif

namespace nodetrace::cachesim {

// A free place: never a block while the stacks are narrow.
inline constexpr std::uint32_t kNarrowEmpty = ~std::uint32_t{0};

// Can the narrow stacks hold `block`? (Blocks are below 2^61: no overflow.)
inline bool fits_narrow(std::uint64_t block) { return ((block + 1) >> 32) == 0; }

// One fetch of `block` in a narrow stack of kDepth (1, 2, 4 or 8) places:
// returns its 0-based place (kDepth: not kept) and puts it on top, the
// places above the one it left (all of them when not kept) moving down.
template <unsigned kDepth>
inline unsigned narrow_access(std::uint32_t* stack, std::uint32_t block) {
  if constexpr (kDepth == 1) {
    const unsigned place = stack[0] != block;
    stack[0] = block;
    return place;
  } else if constexpr (kDepth == 2) {
    std::uint64_t both;
    std::memcpy(&both, stack, sizeof both);
    const auto top = static_cast<std::uint32_t>(both);
    const unsigned place = top == block ? 0 : static_cast<std::uint32_t>(both >> 32) == block ? 1 : 2;
    const std::uint64_t pushed = (both << 32) | block;
    both = place == 0 ? both : pushed;
    std::memcpy(stack, &both, sizeof both);
    return place;
  } else {
    static_assert(kDepth == 4 || kDepth == 8);
#if defined(__SSE2__)
    constexpr unsigned kVectors = kDepth / 4;
    // kMoved[p]: the lanes that take the place above them when the block
    // found at p (or not kept, p = kDepth) goes on top: places 0..p.
    alignas(16) static constexpr std::array<std::array<std::int32_t, kDepth>, kDepth + 1> kMoved = [] {
      std::array<std::array<std::int32_t, kDepth>, kDepth + 1> lanes{};
      for (unsigned p = 0; p <= kDepth; ++p) {
        for (unsigned lane = 0; lane < kDepth; ++lane) lanes[p][lane] = lane <= p ? -1 : 0;
      }
      return lanes;
    }();
    const __m128i wanted = _mm_set1_epi32(static_cast<int>(block));
    __m128i places[kVectors];
    unsigned matched = 1u << kDepth;  // bit kDepth: not kept
    for (unsigned v = 0; v < kVectors; ++v) {
      places[v] = _mm_loadu_si128(reinterpret_cast<const __m128i*>(stack) + v);
      matched |= static_cast<unsigned>(
                     _mm_movemask_ps(_mm_castsi128_ps(_mm_cmpeq_epi32(places[v], wanted))))
                 << (4 * v);
    }
    const auto place = static_cast<unsigned>(std::countr_zero(matched));
    // Each vector's lanes one place down, the lane shifted out of the one
    // above (the block, for the first) coming in at its lane 0.
    __m128i above = _mm_cvtsi32_si128(static_cast<int>(block));
    for (unsigned v = 0; v < kVectors; ++v) {
      const __m128i pushed = _mm_or_si128(_mm_slli_si128(places[v], 4), above);
      above = _mm_srli_si128(places[v], 12);
      const __m128i moved = _mm_load_si128(reinterpret_cast<const __m128i*>(kMoved[place].data()) + v);
      const __m128i kept = _mm_or_si128(_mm_and_si128(moved, pushed), _mm_andnot_si128(moved, places[v]));
      _mm_storeu_si128(reinterpret_cast<__m128i*>(stack) + v, kept);
    }
    return place;
#else
    unsigned place = 0;
    while (place < kDepth && stack[place] != block) ++place;
    for (unsigned p = place < kDepth ? place : kDepth - 1; p > 0; --p) stack[p] = stack[p - 1];
    stack[0] = block;
    return place;
#endif
  }
}

// Fetches counted by the place they were found at, in four histograms in
// turn: with one, a fetch's count waits for the last fetch found at the
// same place (an add to memory each).
template <unsigned kDepth>
struct PlaceHistograms {
  std::uint64_t found_at[4][kDepth + 1] = {};

  void count(std::size_t fetch, unsigned place) { ++found_at[fetch % 4][place]; }
  // Adds places 1..kDepth to deeper[] (place 0 is never counted there).
  void add_to(std::uint64_t* deeper) const {
    for (unsigned place = 1; place <= kDepth; ++place) {
      for (const auto& histogram : found_at) deeper[place] += histogram[place];
    }
  }
};

// Runs `count` fetches (`in[i]`, every one fitting narrow stacks: a
// pointer to blocks, or any view with operator[] that gives them) through
// the narrow stacks of one set count (set = block & mask), adding to
// deeper[p] the fetches found at place p (p = depth: not kept). Writes the
// fetches not found on top to `out` (which may be `in`) and returns how
// many.
template <unsigned kDepth, typename In>
std::size_t run_narrow_set_stacks(std::uint32_t* stacks, std::uint64_t mask, In in, std::size_t count,
                                  std::uint64_t* out, std::uint64_t* deeper) {
  std::size_t passed = 0;
  if constexpr (kDepth == 1) {
    // Every fetch passed on is one not kept: no histogram.
    for (std::size_t i = 0; i < count; ++i) {
      const std::uint64_t block = in[i];
      out[passed] = block;
      passed += narrow_access<1>(stacks + (block & mask), static_cast<std::uint32_t>(block));
    }
    deeper[1] += passed;
    return passed;
  }
  PlaceHistograms<kDepth> found;
  for (std::size_t i = 0; i < count; ++i) {
    const std::uint64_t block = in[i];
    const unsigned place =
        narrow_access<kDepth>(stacks + (block & mask) * kDepth, static_cast<std::uint32_t>(block));
    found.count(i, place);
    out[passed] = block;
    passed += place != 0;
  }
  found.add_to(deeper);
  return passed;
}

#if defined(NODETRACE_NARROW_STACKS_AVX2)
// run_narrow_set_stacks<8> on a processor with AVX2 (the same counts and
// stacks): a stack's 8 places are one 32-byte vector, compared, moved down
// (a lane permutation) and blended at once, about half the instructions of
// two 16-byte vectors.
template <typename In>
__attribute__((target("avx2"))) std::size_t run_narrow_set_stacks_avx2(std::uint32_t* stacks, std::uint64_t mask,
                                                                       In in, std::size_t count, std::uint64_t* out,
                                                                       std::uint64_t* deeper) {
  constexpr unsigned kDepth = 8;
  const __m256i one_down = _mm256_setr_epi32(0, 0, 1, 2, 3, 4, 5, 6);
  const __m256i lanes = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
  PlaceHistograms<kDepth> found;
  std::size_t passed = 0;
  for (std::size_t i = 0; i < count; ++i) {
    const std::uint64_t block = in[i];
    std::uint32_t* const stack = stacks + (block & mask) * kDepth;
    const __m256i wanted = _mm256_set1_epi32(static_cast<int>(block));
    const __m256i places = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(stack));
    const auto matched = static_cast<unsigned>(
        _mm256_movemask_ps(_mm256_castsi256_ps(_mm256_cmpeq_epi32(places, wanted))));
    const auto place = static_cast<unsigned>(std::countr_zero(matched | (1u << kDepth)));
    // Places 0..place take the one above them, the block coming in on top.
    const __m256i pushed = _mm256_blend_epi32(_mm256_permutevar8x32_epi32(places, one_down), wanted, 1);
    const __m256i moved = _mm256_cmpgt_epi32(_mm256_set1_epi32(static_cast<int>(place) + 1), lanes);
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(stack), _mm256_blendv_epi8(places, pushed, moved));
    found.count(i, place);
    out[passed] = block;
    passed += place != 0;
  }
  found.add_to(deeper);
  return passed;
}
#endif

// run_narrow_set_stacks<8> in the widest form this processor runs.
template <typename In>
std::size_t run_narrow_set_stacks_of_8(std::uint32_t* stacks, std::uint64_t mask, In in, std::size_t count,
                                       std::uint64_t* out, std::uint64_t* deeper) {
#if defined(NODETRACE_NARROW_STACKS_AVX2)
  static const bool avx2 = __builtin_cpu_supports("avx2");
  if (avx2) return run_narrow_set_stacks_avx2(stacks, mask, in, count, out, deeper);
#endif
  return run_narrow_set_stacks<8, In>(stacks, mask, in, count, out, deeper);
}

}  // namespace nodetrace::cachesim
