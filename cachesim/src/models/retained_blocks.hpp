// The distinct high-level blocks touched in one animation frame (the
// `retain` high cache), for the simulators.
#pragma once

#include <algorithm>
#include <bit>
#include <cstdint>
#include <vector>

#include "nodetrace/cachesim/models/set_associative_cache.hpp"

namespace nodetrace::cachesim {

// The distinct high-level blocks touched in the current animation frame
// (`retain`): an open-addressing set cleared in O(1) per frame by an epoch.
class RetainedBlocks {
 public:
  explicit RetainedBlocks(std::uint64_t capacity_blocks) : capacity_(capacity_blocks) {
    const std::uint64_t slots = std::bit_ceil(std::max<std::uint64_t>(16, 2 * (capacity_ + 1)));
    keys_.resize(slots);
    stamps_.assign(slots, 0);
    mask_ = slots - 1;
    hash_shift_ = 64 - static_cast<unsigned>(std::countr_zero(slots));
  }

  std::uint64_t capacity() const { return capacity_; }
  std::uint64_t count() const { return count_; }

  void clear() {
    count_ = 0;
    last_ = SetAssociativeCache::kInvalid;
    if (++epoch_ == 0) {
      std::fill(stamps_.begin(), stamps_.end(), 0);
      epoch_ = 1;
    }
  }

  // True when `block` is new this frame.
  bool insert(std::uint64_t block) {
    if (block == last_) return false;
    last_ = block;
    std::uint64_t slot = (block * 0x9E3779B97F4A7C15ull) >> hash_shift_;
    while (true) {
      if (stamps_[slot] != epoch_) {
        stamps_[slot] = epoch_;
        keys_[slot] = block;
        ++count_;
        return true;
      }
      if (keys_[slot] == block) return false;
      slot = (slot + 1) & mask_;
    }
  }

 private:
  std::uint64_t capacity_;
  std::vector<std::uint64_t> keys_;
  std::vector<std::uint32_t> stamps_;
  std::uint32_t epoch_ = 1;
  std::uint64_t mask_ = 0;
  unsigned hash_shift_ = 0;
  std::uint64_t count_ = 0;
  std::uint64_t last_ = SetAssociativeCache::kInvalid;
};

}  // namespace nodetrace::cachesim
