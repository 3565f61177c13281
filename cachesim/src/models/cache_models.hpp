// The cache models a configuration's simulator is composed of (see
// config_simulator.cpp): a direct-mapped table, a set-associative cache, the
// retain set of the split scheme's high cache, and no cache (the high side
// of `single`). Each takes block numbers; the table and the retain set
// expose their slots so the fast loops can pick one without a branch.
#pragma once

#include <algorithm>
#include <bit>
#include <cstdint>
#include <vector>

#include "nodetrace/cachesim/models/set_associative_cache.hpp"
#include "models/retained_blocks.hpp"

namespace nodetrace::cachesim {

// A direct-mapped cache: one block per set, so no policy.
class DirectMappedTable {
 public:
  explicit DirectMappedTable(std::uint64_t sets) : slots_(sets, SetAssociativeCache::kInvalid), mask_(sets - 1) {}
  bool access(std::uint64_t block) {
    std::uint64_t& slot = slots_[block & mask_];
    const bool miss = slot != block;
    slot = block;
    return miss;
  }
  void invalidate(std::uint64_t block) {
    if (std::uint64_t& slot = slots_[block & mask_]; slot == block) slot = SetAssociativeCache::kInvalid;
  }
  void clear() { std::fill(slots_.begin(), slots_.end(), SetAssociativeCache::kInvalid); }
  std::uint64_t* slots() { return slots_.data(); }
  std::uint64_t mask() const { return mask_; }

 private:
  std::vector<std::uint64_t> slots_;
  std::uint64_t mask_;
};

// The `retain` high cache: the distinct blocks touched in the current
// animation frame, loaded once each. A direct-mapped filter of blocks
// already loaded answers most fetches with one compare.
class RetainSet {
 public:
  explicit RetainSet(std::uint64_t capacity_blocks)
      : filter_(std::bit_ceil(std::max<std::uint64_t>(64, 4 * capacity_blocks))),
        blocks_(capacity_blocks) {}
  // True when `block` is a new load this frame (then count() may exceed
  // capacity(): the caller's error).
  bool access(std::uint64_t block) {
    std::uint64_t& slot = filter_.slots()[block & filter_.mask()];
    if (slot == block) return false;
    slot = block;
    return blocks_.insert(block);
  }
  // For the fast loops: the filter missed (`block` is in its slot now).
  [[gnu::noinline]] bool insert_after_filter(std::uint64_t block) { return blocks_.insert(block); }
  void begin_animation_frame() {
    blocks_.clear();
    filter_.clear();
  }
  std::uint64_t count() const { return blocks_.count(); }
  std::uint64_t capacity() const { return blocks_.capacity(); }
  DirectMappedTable& filter() { return filter_; }

 private:
  DirectMappedTable filter_;
  RetainedBlocks blocks_;
};

// The high side of `single`: never reached.
struct NoCache {
  bool access(std::uint64_t) { return false; }
  void invalidate(std::uint64_t) {}
};

}  // namespace nodetrace::cachesim
