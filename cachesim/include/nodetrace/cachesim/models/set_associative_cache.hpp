// A specialised node cache: one cache level, flat tag arrays, demand fetch,
// write-allocate (so reads and writes miss alike, as in Dinero IV's default
// write-allocate / write-back caches). Miss counts equal Dinero IV's for LRU,
// FIFO and random: random draws Dinero IV's sequence (glibc's random() after
// srandom(1), one generator per cache, as one Dinero IV process per cache
// draws) and evicts as Dinero IV does. The other policies are
// PolicyCache's and OptCache's (cachesim/src/models).
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "nodetrace/cachesim/models/cache_geometry.hpp"

namespace nodetrace::cachesim {

namespace detail {
class LibcRandom;
}

class SetAssociativeCache {
 public:
  static constexpr std::uint64_t kInvalid = ~std::uint64_t{0};

  // Throws base::UsageError for a bad geometry or a policy other than lru,
  // fifo and random.
  explicit SetAssociativeCache(const CacheGeometry& geometry);
  SetAssociativeCache(SetAssociativeCache&&) noexcept;
  SetAssociativeCache& operator=(SetAssociativeCache&&) noexcept;
  ~SetAssociativeCache();

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
  // sets * assoc block numbers. Each set is ordered most recent (LRU: used,
  // FIFO and random: filled) first, invalid entries last.
  std::vector<std::uint64_t> tags_;
  std::unique_ptr<detail::LibcRandom> random_;  // random only
};

}  // namespace nodetrace::cachesim
