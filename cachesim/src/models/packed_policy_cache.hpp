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

// What one reference of a list asks of a packed cache.
// Fetch | 1 is Refetched.
enum class PackedReference : std::uint8_t {
  Fetch = 0,      // a demand fetch
  Refetched = 1,  // a demand fetch whose block is fetched again before any other block of its set
  Invalidate = 2,
};

template <typename State, unsigned kWays>
class PackedPolicyCache {
 public:
  explicit PackedPolicyCache(const CacheGeometry& geometry)
      : set_mask_(geometry.size / geometry.block_size / kWays - 1),
        narrow_((set_mask_ + 1) * kWays, ~std::uint32_t{0}),
        state_(set_mask_ + 1, geometry) {}

  // From now on tags are 64 bits (a block number of 2^32 - 1 or more came).
  void widen() {
    wide_.resize(narrow_.size());
    for (std::size_t slot = 0; slot < narrow_.size(); ++slot) {
      wide_[slot] = narrow_[slot] == ~std::uint32_t{0} ? ~std::uint64_t{0} : narrow_[slot];
    }
    narrow_ = {};
  }

  std::uint64_t misses() const { return misses_; }

  // One demand fetch of `block` (`refetched`: a Refetched reference, see
  // run()). Inline, for callers that run several caches over the same
  // references in one loop (packed_cache_bundle.hpp).
  template <typename Tag>
  void access(std::uint64_t block, bool refetched) {
    const std::uint64_t set = block & set_mask_;
    Tag* const ways = tags<Tag>() + set * kWays;
    const auto tag = static_cast<Tag>(block);
    Word* const word = state_.words() + set;
    const std::uint32_t found = match_ways<kWays>(ways, tag);
    if (found != 0) [[likely]] {
      *word = State::hit(*word, static_cast<std::uint32_t>(std::countr_zero(found)));
      return;
    }
    // A miss: the lowest invalid way, else the victim. Once every way
    // holds a block (unless invalidations free some) no set is searched
    // for a free one.
    ++misses_;
    std::uint32_t invalid = 0;
    if (invalid_ways_ != 0) [[unlikely]] {
      invalid = match_ways<kWays>(ways, static_cast<Tag>(~Tag{0}));
      invalid_ways_ -= invalid != 0;
    }
    const bool evicted = invalid == 0;
    const std::uint32_t way = evicted ? State::victim(*word) : static_cast<std::uint32_t>(std::countr_zero(invalid));
    ways[way] = tag;
    *word = state_.fill(*word, way, set, evicted, refetched);
  }

  // `count` references in order, some of them invalidations (a list of
  // fetches only goes through access() alone). A Refetched fetch stands for
  // itself and the fetches of its block that follow it before any other
  // fetch of its set: those hit,
  // and a hit's update is idempotent (PLRU points the same bits away again,
  // RRIP sets the same value to 0 again, neither counts hits), so they
  // change the set as one hit does. After a hit that is this fetch's update
  // again; after a fill it is not (RRIP: 0, not the insertion value), so it
  // is applied once.
  template <typename Tag>
  void run(const std::uint64_t* blocks, const PackedReference* kinds, std::size_t count) {
    for (std::size_t r = 0; r < count; ++r) {
      if (kinds[r] == PackedReference::Invalidate) [[unlikely]] {
        invalidate<Tag>(blocks[r]);
        continue;
      }
      access<Tag>(blocks[r], kinds[r] == PackedReference::Refetched);
    }
  }

  // Leaves `block`'s way invalid, if it holds it; the policy state stays.
  template <typename Tag>
  void invalidate(std::uint64_t block) {
    Tag* const ways = tags<Tag>() + (block & set_mask_) * kWays;
    const std::uint32_t found = match_ways<kWays>(ways, static_cast<Tag>(block));
    if (found != 0) {
      ways[std::countr_zero(found)] = static_cast<Tag>(~Tag{0});
      ++invalid_ways_;
    }
  }

 private:
  using Word = typename State::Word;

  template <typename Tag>
  Tag* tags() {
    if constexpr (sizeof(Tag) == 4) {
      return narrow_.data();
    } else {
      return wide_.data();
    }
  }

  std::uint64_t set_mask_;
  std::vector<std::uint32_t> narrow_;  // sets * kWays tags, until widen()
  std::vector<std::uint64_t> wide_;    // after widen()
  State state_;
  std::uint64_t invalid_ways_ = (set_mask_ + 1) * kWays;  // ways holding no block, in all sets
  std::uint64_t misses_ = 0;
};

}  // namespace nodetrace::cachesim
