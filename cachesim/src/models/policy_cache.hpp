// Internal: a set-associative cache whose replacement is a policy object
// (replacement_policies.hpp): recency lists for LRU, FIFO and Dinero IV's
// random of many ways, tree pseudo-LRU, RRIP. Sets of more than kScanWays
// ways find a block through a BlockIndex, not way by way. A miss fills the
// lowest-numbered invalid way of its set, if there is one; otherwise the
// policy's victim.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "models/block_index.hpp"
#include "nodetrace/cachesim/models/cache_geometry.hpp"

namespace nodetrace::cachesim {

inline constexpr std::uint32_t kScanWays = 16;

template <typename Policy>
class PolicyCache {
 public:
  static constexpr std::uint64_t kInvalid = ~std::uint64_t{0};
  static constexpr std::uint32_t kNone = ~std::uint32_t{0};

  explicit PolicyCache(const CacheGeometry& geometry)
      : assoc_(validated(geometry).assoc),
        set_mask_(geometry.size / geometry.block_size / geometry.assoc - 1),
        tags_(geometry.size / geometry.block_size, kInvalid),
        filled_(set_mask_ + 1, 0),
        policy_(set_mask_ + 1, geometry) {
    if (assoc_ > kScanWays) index_.emplace(tags_.size());
  }

  // True on a miss (the block is then resident). The hit path is small
  // enough to be inlined into the simulator's loop, the miss path is not.
  bool access(std::uint64_t block) {
    const std::uint64_t set = block & set_mask_;
    std::uint64_t* const ways = tags_.data() + set * assoc_;
    const std::uint32_t way = find(ways, set, block);
    if (way != kNone) [[likely]] {
      policy_.hit(set, way);
      return false;
    }
    fill(block, set, ways);
    return true;
  }

  // As access(); `slot` is then where the block is (set * ways + way), so
  // a caller can keep a mark per resident block (the treelet prefetcher).
  bool access(std::uint64_t block, std::uint64_t& slot) {
    const std::uint64_t set = block & set_mask_;
    std::uint64_t* const ways = tags_.data() + set * assoc_;
    std::uint32_t way = find(ways, set, block);
    const bool miss = way == kNone;
    if (!miss) [[likely]] {
      policy_.hit(set, way);
    } else {
      way = fill(block, set, ways);
    }
    slot = set * assoc_ + way;
    return miss;
  }

  // Places `block` as a miss would (the policy's insertion), unless it is
  // resident: then nothing changes. Returns its slot, or kNoSlot when it was resident.
  static constexpr std::uint64_t kNoSlot = ~std::uint64_t{0};
  std::uint64_t place(std::uint64_t block) {
    const std::uint64_t set = block & set_mask_;
    std::uint64_t* const ways = tags_.data() + set * assoc_;
    if (find(ways, set, block) != kNone) return kNoSlot;
    return set * assoc_ + fill(block, set, ways);
  }

  void invalidate(std::uint64_t block) { invalidate_slot(block); }

  // invalidate(); returns the slot the block left, or kNoSlot when it was not resident.
  std::uint64_t invalidate_slot(std::uint64_t block) {
    const std::uint64_t set = block & set_mask_;
    std::uint64_t* const ways = tags_.data() + set * assoc_;
    const std::uint32_t way = find(ways, set, block);
    if (way == kNone) return kNoSlot;
    ways[way] = kInvalid;
    --filled_[set];
    if (index_) index_->erase(block);
    policy_.invalidate(set, way);
    return set * assoc_ + way;
  }

  std::uint64_t slots() const { return tags_.size(); }

 private:
  // A miss: `block` takes the lowest invalid way of its set, or the policy's victim.
  // Returns the way it took.
  [[gnu::noinline]] std::uint32_t fill(std::uint64_t block, std::uint64_t set, std::uint64_t* ways) {
    std::uint32_t way = 0;
    if (filled_[set] < assoc_) {
      while (ways[way] != kInvalid) ++way;
      ++filled_[set];
    } else {
      way = policy_.victim(set);
      if (index_) index_->erase(ways[way]);
    }
    ways[way] = block;
    if (index_) index_->insert(block, static_cast<std::uint32_t>(set * assoc_ + way));
    policy_.fill(set, way);
    return way;
  }

  static const CacheGeometry& validated(const CacheGeometry& geometry) {
    validate_geometry(geometry, "cache");
    return geometry;
  }

  std::uint32_t find(const std::uint64_t* ways, std::uint64_t set, std::uint64_t block) const {
    if (index_) {
      const std::uint32_t slot = index_->find(block);
      return slot == BlockIndex::kAbsent ? kNone : static_cast<std::uint32_t>(slot - set * assoc_);
    }
    for (std::uint32_t way = 0; way < assoc_; ++way) {
      if (ways[way] == block) return way;
    }
    return kNone;
  }

  std::uint32_t assoc_;
  std::uint64_t set_mask_;
  std::vector<std::uint64_t> tags_;     // sets * assoc block numbers, kInvalid when free
  std::vector<std::uint32_t> filled_;   // valid ways per set
  std::optional<BlockIndex> index_;     // block -> slot, for sets of many ways
  Policy policy_;
};

}  // namespace nodetrace::cachesim
