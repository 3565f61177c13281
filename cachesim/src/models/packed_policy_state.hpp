// Internal: the state of tree pseudo-LRU and of RRIP kept in one small
// integer per set (a word), for PackedPolicyCache (packed_policy_cache.hpp).
// The rules are replacement_policies.hpp's (TreePlru, Rrip) and the
// docs/guide/replacement-policies.md's; only the storage differs: a set's
// state is one load and one store, and a victim is found with bit
// operations.
#pragma once

#include <array>
#include <bit>
#include <cstdint>
#include <type_traits>
#include <vector>

#include "models/replacement_policies.hpp"
#include "nodetrace/cachesim/models/cache_geometry.hpp"

namespace nodetrace::cachesim {

// The smallest unsigned integer of at least `kBits` bits.
template <unsigned kBits>
using PackedBits = std::conditional_t<
    kBits <= 8, std::uint8_t,
    std::conditional_t<kBits <= 16, std::uint16_t, std::conditional_t<kBits <= 32, std::uint32_t, std::uint64_t>>>;

// Tree pseudo-LRU: node n of the tree (1 the root, children 2n and 2n + 1,
// leaves kWays + way) is bit n of the set's word and points to the half to
// evict from. A hit or a fill points every bit on the way's path away from
// it: clear the path's bits, then set those that point away.
template <unsigned kWays>
class PackedPlru {
 public:
  using Word = PackedBits<kWays>;

  PackedPlru(std::uint64_t sets, const CacheGeometry&) : words_(sets, 0) {}

  Word* words() { return words_.data(); }
  // The way a miss in a full set evicts (a fixed number of steps).
  static std::uint32_t victim(Word bits) {
    std::uint32_t node = 1;
    while (node < kWays) node = 2 * node + ((bits >> node) & 1u);
    return node - kWays;
  }
  static Word hit(Word bits, std::uint32_t way) {
    return static_cast<Word>((bits & ~kPaths.path[way]) | kPaths.away[way]);
  }
  // A fill points the bits away as a hit does (`evicted`: into a full
  // set; `refetched`: hit next).
  Word fill(Word bits, std::uint32_t way, std::uint64_t, bool, bool) { return hit(bits, way); }

 private:
  struct Paths {
    std::array<Word, kWays> path{};  // the nodes above each way
    std::array<Word, kWays> away{};  // of those, the ones whose bit is 1 when pointing away
  };
  static constexpr Paths paths() {
    Paths paths;
    for (std::uint32_t way = 0; way < kWays; ++way) {
      for (std::uint32_t node = kWays + way; node > 1; node /= 2) {
        const std::uint32_t parent = node / 2;
        paths.path[way] = static_cast<Word>(paths.path[way] | (1u << parent));
        // The way is in the left half (node even): the bit points right (1).
        if (node % 2 == 0) paths.away[way] = static_cast<Word>(paths.away[way] | (1u << parent));
      }
    }
    return paths;
  }
  static constexpr Paths kPaths = paths();

  std::vector<Word> words_;  // per set
};

// Re-reference interval prediction: each way's 2-bit value is bits 2w and
// 2w + 1 of the set's word; a fill takes RripInsertion's value.
template <unsigned kWays>
class PackedRrip {
 public:
  using Word = PackedBits<2 * kWays>;

  PackedRrip(std::uint64_t sets, const CacheGeometry& geometry)
      : words_(sets, kLowBits * 3), insertion_(sets, geometry.replacement) {}

  Word* words() { return words_.data(); }
  // The lowest way at 3 (distant), after ageing the whole set by 3 minus
  // its highest value when none is.
  static std::uint32_t victim(Word values) {
    const Word aged = age(values);
    return static_cast<std::uint32_t>(std::countr_zero(distant(aged))) / 2;
  }
  static Word hit(Word values, std::uint32_t way) { return static_cast<Word>(values & ~(Word{3} << (2 * way))); }
  // The insertion value, or 0 for a block `refetched` (it hits next), in a
  // set aged first when the fill `evicted` a block.
  Word fill(Word values, std::uint32_t way, std::uint64_t set, bool evicted, bool refetched) {
    const std::uint8_t inserted = insertion_(set);  // counts every fill
    const Word value = refetched ? Word{0} : Word{inserted};
    return static_cast<Word>(hit(evicted ? age(values) : values, way) | (value << (2 * way)));
  }

 private:
  // Bit 0 of each way's field (0x55...), of kWays fields only: a wider
  // word's spare fields must never look distant.
  static constexpr Word low_bits() {
    Word bits = 0;
    for (unsigned way = 0; way < kWays; ++way) bits = static_cast<Word>(bits | (Word{1} << (2 * way)));
    return bits;
  }
  static constexpr Word kLowBits = low_bits();

  // Bit 2w set when way w is at 3.
  static Word distant(Word values) { return static_cast<Word>((values >> 1) & values & kLowBits); }
  // Every value raised by 3 minus the highest, none overflowing (highest
  // + age = 3).
  static Word age(Word values) {
    const bool none_distant = distant(values) == 0;
    const bool some_high = ((values >> 1) & kLowBits) != 0;  // at 2, when none is at 3
    const bool some_low = (values & kLowBits) != 0;
    const unsigned steps = none_distant * (1u + !some_high * (1u + !some_low));
    return static_cast<Word>(values + steps * kLowBits);
  }

  std::vector<Word> words_;  // per set
  RripInsertion insertion_;
};

}  // namespace nodetrace::cachesim
