// A specialised node cache: one cache level, flat tag arrays, demand fetch,
// write-allocate (so reads and writes miss alike, as in Dinero IV's default
// write-allocate / write-back caches). Miss counts equal Dinero IV's for LRU
// and FIFO; random replacement is deterministic (seeded) but its choices are
// not Dinero IV's.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "nodetrace/cachesim/models/cache_geometry.hpp"

namespace nodetrace::cachesim {

class SetAssociativeCache {
 public:
  static constexpr std::uint64_t kInvalid = ~std::uint64_t{0};

  explicit SetAssociativeCache(const CacheGeometry& geometry, std::uint64_t seed = 0x5eed);

  // References block number `block` (address >> log2(block size)); returns true
  // on a miss, after which the block is resident.
  bool access(std::uint64_t block) {
    if (assoc_ == 1) {
      std::uint64_t& slot = tags_[block & set_mask_];
      if (slot == block) return false;
      slot = block;
      return true;
    }
    return access_associative(block);
  }

  // Removes `block` if resident (Dinero IV's invalidate records).
  void invalidate(std::uint64_t block);

  std::uint64_t sets() const { return set_mask_ + 1; }
  // Sets the contents of set `set`: `ways` blocks, most recently used first,
  // kInvalid for free ways (an LRU cache's state as SetStacks::ways_of gives it).
  void assign_set(std::uint64_t set, const std::vector<std::uint64_t>& ways);

 private:
  bool access_associative(std::uint64_t block);

  CacheGeometry geometry_;
  std::uint32_t assoc_ = 1;
  std::uint64_t set_mask_ = 0;
  // sets * assoc block numbers. For LRU and FIFO each set is ordered most
  // recent (LRU: used, FIFO: filled) first, invalid entries last; for random
  // the order is the fill order of the ways.
  std::vector<std::uint64_t> tags_;
  std::uint64_t random_state_;
};

}  // namespace nodetrace::cachesim
