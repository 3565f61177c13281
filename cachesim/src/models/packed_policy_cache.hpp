// Internal: a set-associative cache of a few ways (a power of two, at most
// kMaxPackedWays) under tree pseudo-LRU or RRIP, kept compact for the policy
// grid (sweep/policy_grid.cpp): each set's tags side by side, searched in
// vectors (way_match.hpp), and its policy state in one integer
// (packed_policy_state.hpp). It misses exactly as PolicyCache with TreePlru
// or Rrip: a miss fills the lowest-numbered invalid way of its set, if there
// is one; otherwise the policy's victim.
//
// Tags are whole block numbers, 32 bits while every block number is below
// 2^32 - 1 (half the bytes to keep in the processor's cache), 64 bits after
// widen(); the all-ones tag marks an invalid way.
#pragma once

#include <bit>
#include <cstdint>
#include <vector>

#include "models/packed_policy_state.hpp"
#include "models/way_match.hpp"
#include "nodetrace/cachesim/models/cache_geometry.hpp"

namespace nodetrace::cachesim {

inline constexpr std::uint32_t kMaxPackedWays = 16;

// Blocks below this fit a narrow (32-bit) tag.
inline constexpr std::uint64_t kNarrowBlocks = 0xFFFFFFFF;

template <typename State, unsigned kWays>
class PackedPolicyCache {
 public:
  explicit PackedPolicyCache(const CacheGeometry& geometry)
      : set_mask_(geometry.size / geometry.block_size / kWays - 1),
        narrow_((set_mask_ + 1) * kWays, ~std::uint32_t{0}),
        state_(set_mask_ + 1, geometry) {}

  bool wide() const { return !wide_.empty(); }
  // From now on tags are 64 bits (a block number of 2^32 - 1 or more came).
  void widen() {
    wide_.resize(narrow_.size());
    for (std::size_t slot = 0; slot < narrow_.size(); ++slot) {
      wide_[slot] = narrow_[slot] == ~std::uint32_t{0} ? ~std::uint64_t{0} : narrow_[slot];
    }
    narrow_ = {};
  }

  // True on a miss (the block is then resident). `repeated`: the reference
  // is followed by more of the same block, before any other reference or
  // invalidation. They all hit and re-apply the hit's update, which is
  // idempotent (PLRU points the same bits away again, RRIP sets the same
  // value to 0 again, and neither counts hits), so one hit stands for all.
  // After a hit that hit is this one's update again; after a fill it is not
  // (RRIP: 0, not the insertion value), so it is applied.
  template <typename Tag>
  bool access(std::uint64_t block, bool repeated) {
    const std::uint64_t set = block & set_mask_;
    Tag* const ways = tags<Tag>() + set * kWays;
    const auto tag = static_cast<Tag>(block);
    const std::uint32_t found = match_ways<kWays>(ways, tag);
    if (found != 0) [[likely]] {
      state_.hit(set, static_cast<std::uint32_t>(std::countr_zero(found)));
      return false;
    }
    const std::uint32_t way = fill(ways, tag, set);
    if (repeated) state_.hit(set, way);
    return true;
  }

  // The block's way, if resident, becomes invalid (the policy state is left
  // as it is, as PolicyCache leaves it).
  template <typename Tag>
  void invalidate(std::uint64_t block) {
    Tag* const ways = tags<Tag>() + (block & set_mask_) * kWays;
    const std::uint32_t found = match_ways<kWays>(ways, static_cast<Tag>(block));
    if (found != 0) ways[std::countr_zero(found)] = static_cast<Tag>(~Tag{0});
  }

 private:
  template <typename Tag>
  Tag* tags() {
    if constexpr (sizeof(Tag) == 4) {
      return narrow_.data();
    } else {
      return wide_.data();
    }
  }

  // A miss: the lowest invalid way of the set, or the policy's victim.
  template <typename Tag>
  [[gnu::noinline]] std::uint32_t fill(Tag* ways, Tag tag, std::uint64_t set) {
    const std::uint32_t invalid = match_ways<kWays>(ways, static_cast<Tag>(~Tag{0}));
    const std::uint32_t way =
        invalid != 0 ? static_cast<std::uint32_t>(std::countr_zero(invalid)) : state_.victim(set);
    ways[way] = tag;
    state_.fill(set, way);
    return way;
  }

  std::uint64_t set_mask_;
  std::vector<std::uint32_t> narrow_;  // sets * kWays tags, until widen()
  std::vector<std::uint64_t> wide_;    // after widen()
  State state_;
};

}  // namespace nodetrace::cachesim
