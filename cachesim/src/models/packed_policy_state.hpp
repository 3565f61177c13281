// Internal: the state of tree pseudo-LRU and of RRIP kept in one small
// integer per set, for PackedPolicyCache (packed_policy_cache.hpp). The
// rules are replacement_policies.hpp's (TreePlru, Rrip) and the README's
// ("Replacement policies"); only the storage differs: a set's state is one
// load and one store, and a victim is found with bit operations.
#pragma once

#include <algorithm>
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
// leaves kWays + way) is bit n of the set's integer and points to the half
// to evict from. A hit or a fill points every bit on the way's path away
// from it: clear the path's bits, then set those that point away.
template <unsigned kWays>
class PackedPlru {
 public:
  using Bits = PackedBits<kWays>;

  PackedPlru(std::uint64_t sets, const CacheGeometry&) : bits_(sets, 0) {}

  void hit(std::uint64_t set, std::uint32_t way) {
    bits_[set] = static_cast<Bits>((bits_[set] & ~kPaths.path[way]) | kPaths.away[way]);
  }
  std::uint32_t victim(std::uint64_t set) const {
    const Bits bits = bits_[set];
    std::uint32_t node = 1;
    while (node < kWays) node = 2 * node + ((bits >> node) & 1u);
    return node - kWays;
  }
  void fill(std::uint64_t set, std::uint32_t way) { hit(set, way); }

 private:
  struct Paths {
    std::array<Bits, kWays> path{};  // the nodes above each way
    std::array<Bits, kWays> away{};  // of those, the ones whose bit is 1 when pointing away
  };
  static constexpr Paths paths() {
    Paths paths;
    for (std::uint32_t way = 0; way < kWays; ++way) {
      for (std::uint32_t node = kWays + way; node > 1; node /= 2) {
        const std::uint32_t parent = node / 2;
        paths.path[way] = static_cast<Bits>(paths.path[way] | (1u << parent));
        // The way is in the left half (node even): the bit points right (1).
        if (node % 2 == 0) paths.away[way] = static_cast<Bits>(paths.away[way] | (1u << parent));
      }
    }
    return paths;
  }
  static constexpr Paths kPaths = paths();

  std::vector<Bits> bits_;  // per set
};

// Re-reference interval prediction: each way's 2-bit value is bits 2w and
// 2w + 1 of the set's integer; a fill takes RripInsertion's value.
template <unsigned kWays>
class PackedRrip {
 public:
  using Values = PackedBits<2 * kWays>;

  PackedRrip(std::uint64_t sets, const CacheGeometry& geometry)
      : values_(sets, static_cast<Values>(~Values{0})), insertion_(sets, geometry.replacement) {}

  void hit(std::uint64_t set, std::uint32_t way) {
    values_[set] = static_cast<Values>(values_[set] & ~(Values{3} << (2 * way)));
  }
  // The lowest way at 3 (distant), after ageing the whole set by 3 minus
  // its highest value when none is. No field overflows: highest + age = 3.
  std::uint32_t victim(std::uint64_t set) {
    Values values = values_[set];
    Values distant = static_cast<Values>((values >> 1) & values & kLowBits);
    if (distant == 0) {
      const Values high = static_cast<Values>((values >> 1) & kLowBits);  // ways at 2 or 3
      const unsigned highest = high != 0 ? 2 : ((values & kLowBits) != 0 ? 1 : 0);
      values = static_cast<Values>(values + (3 - highest) * kLowBits);
      values_[set] = values;
      distant = static_cast<Values>((values >> 1) & values & kLowBits);
    }
    return static_cast<std::uint32_t>(std::countr_zero(distant)) / 2;
  }
  void fill(std::uint64_t set, std::uint32_t way) {
    const Values value = insertion_(set);
    values_[set] = static_cast<Values>((values_[set] & ~(Values{3} << (2 * way))) | (value << (2 * way)));
  }

 private:
  // Bit 0 of each way's field (0x55...), of kWays fields only: a wider
  // integer's spare fields must never look distant.
  static constexpr Values low_bits() {
    Values bits = 0;
    for (unsigned way = 0; way < kWays; ++way) bits = static_cast<Values>(bits | (Values{1} << (2 * way)));
    return bits;
  }
  static constexpr Values kLowBits = low_bits();

  std::vector<Values> values_;  // per set
  RripInsertion insertion_;
};

}  // namespace nodetrace::cachesim
