// Internal: the stacks of one set count (SetStacks, set_stacks.hpp) run
// over a list of fetches in order, passing on the fetches whose block was
// not on top of its set (the only ones a larger set count must see). A
// stack of an even depth is searched and moved in 16-byte vectors (GCC and
// Clang vector extensions, no intrinsics): the block found at place p, or
// the oldest when it is not kept, makes room by shifting places 0..p-1
// down one, a lane shuffle and a select per two places, so no branch
// depends on where a block was found (a rendered trace's places are
// random).
#pragma once

#include <bit>
#include <cstdint>
#include <cstring>

namespace nodetrace::cachesim {

// Runs `count` fetches (`in`) through stacks of `depth` blocks each (set =
// block & mask, most recent first), adding to deeper[p] the fetches found
// at 0-based place p (p = depth: not kept). Writes the fetches not found
// on top to `out` (which may be `in`: it is written behind the read) and
// returns how many.
template <unsigned kDepth>
std::size_t run_set_stacks(std::uint64_t* stacks, std::uint64_t mask, const std::uint64_t* in,
                           std::size_t count, std::uint64_t* out, std::uint64_t* deeper);

// One block deep (direct mapped): a fetch is either on top or a miss.
template <>
inline std::size_t run_set_stacks<1>(std::uint64_t* stacks, std::uint64_t mask, const std::uint64_t* in,
                                     std::size_t count, std::uint64_t* out, std::uint64_t* deeper) {
  std::size_t passed = 0;
  for (std::size_t i = 0; i < count; ++i) {
    const std::uint64_t block = in[i];
    std::uint64_t& slot = stacks[block & mask];
    out[passed] = block;
    passed += slot != block;
    slot = block;
  }
  deeper[1] += passed;
  return passed;
}

// Stacks of an even depth (2, 4, 8, 16), as 16-byte vectors of two places.
template <unsigned kDepth>
std::size_t run_set_stacks(std::uint64_t* stacks, std::uint64_t mask, const std::uint64_t* in,
                           std::size_t count, std::uint64_t* out, std::uint64_t* deeper) {
  static_assert(kDepth % 2 == 0 && kDepth <= 32);
  // The comparisons are of 32-bit lanes, which every target has (SSE2 has
  // no 64-bit equality nor any unsigned order): a place matches when both
  // its halves do; place indices are small signed numbers.
  using Pair [[gnu::vector_size(16)]] = std::uint64_t;
  using Halves [[gnu::vector_size(16)]] = std::int32_t;
  constexpr unsigned kPairs = kDepth / 2;
  Halves places[kPairs];  // pair j: places 2j, 2j + 1, in both halves
  Pair weights[kPairs];   // pair j: bits 2j, 2j + 1
  for (unsigned j = 0; j < kPairs; ++j) {
    const auto first = static_cast<std::int32_t>(2 * j);
    places[j] = Halves{first, first, first + 1, first + 1};
    weights[j] = Pair{std::uint64_t{1} << (2 * j), std::uint64_t{2} << (2 * j)};
  }
  std::uint64_t found_at[kDepth + 1] = {};
  std::size_t passed = 0;
  for (std::size_t i = 0; i < count; ++i) {
    const std::uint64_t block = in[i];
    std::uint64_t* const set = stacks + (block & mask) * kDepth;
    Pair stack[kPairs];
    std::memcpy(stack, set, sizeof stack);
    const Pair blocks = Pair{} + block;
    Pair hits{};
    for (unsigned j = 0; j < kPairs; ++j) {
      const Halves same = reinterpret_cast<Halves>(stack[j]) == reinterpret_cast<Halves>(blocks);
      const Halves both = same & __builtin_shufflevector(same, same, 1, 0, 3, 2);
      hits |= reinterpret_cast<Pair>(both) & weights[j];
    }
    // Bit kDepth stands for "not kept": then the oldest place makes room.
    const std::uint64_t matched = hits[0] | hits[1] | (std::uint64_t{1} << kDepth);
    const auto place = static_cast<unsigned>(std::countr_zero(matched));
    const Halves moved = Halves{} + static_cast<std::int32_t>(place < kDepth ? place : kDepth - 1);
    // Places 0..moved take the block and the places above them; the rest stay.
    Pair above = blocks;  // its lane 1: what moves into place 0
    for (unsigned j = 0; j < kPairs; ++j) {
      const Pair pushed = __builtin_shufflevector(above, stack[j], 1, 2);
      const Pair shift = reinterpret_cast<Pair>(places[j] <= moved);
      above = stack[j];
      stack[j] = (pushed & shift) | (stack[j] & ~shift);
    }
    std::memcpy(set, stack, sizeof stack);
    ++found_at[place];
    out[passed] = block;
    passed += place != 0;
  }
  for (unsigned place = 1; place <= kDepth; ++place) deeper[place] += found_at[place];
  return passed;
}

// Any other depth: a plain search and move.
inline std::size_t run_set_stacks_any(std::uint64_t* stacks, std::uint64_t mask, std::uint32_t depth,
                                      const std::uint64_t* in, std::size_t count, std::uint64_t* out,
                                      std::uint64_t* deeper) {
  std::size_t passed = 0;
  for (std::size_t i = 0; i < count; ++i) {
    const std::uint64_t block = in[i];
    std::uint64_t* const set = stacks + (block & mask) * depth;
    std::uint32_t place = 0;
    while (place < depth && set[place] != block) ++place;
    const std::uint32_t moved = place < depth ? place : depth - 1;
    for (std::uint32_t p = moved; p > 0; --p) set[p] = set[p - 1];
    set[0] = block;
    ++deeper[place];
    out[passed] = block;
    passed += place != 0;
  }
  return passed;
}

}  // namespace nodetrace::cachesim
