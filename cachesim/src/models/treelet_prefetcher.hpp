// Internal: a cache that prefetches treelets (`cachesim run --prefetch
// treelet`, nodetrace/cachesim/sweep/treelet_prefetch.hpp). A cache of any
// policy but opt (a PolicyCache, or MarkedRecencySets for LRU and FIFO of
// few ways), with a mark per block that a prefetch placed and no demand
// fetch has used yet: a demand hit on a marked block is
// a useful prefetch. Prefetched blocks enter as the policy inserts a missed
// one (LRU: most recent; FIFO, random: newest filled; PLRU: the tree points
// away; RRIP: the insertion value, counting towards BRRIP's every 32nd).
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "models/policy_cache.hpp"
#include "models/prefetch_demand.hpp"
#include "nodetrace/cachesim/sweep/treelet_prefetch.hpp"
#include "nodetrace/formats/container/treelet_map.hpp"

namespace nodetrace::cachesim {

// The byte range [first, end) a miss on the block at `block_first` (of
// `block_bytes` bytes) prefetches under `map` and `limit` (0: none): from the
// block's first byte to the end of its treelet, cut at `limit` bytes from the
// block's first byte. Its treelet holds the block's first byte, or else is
// the first one that begins inside the block. nullopt: no treelet there.
struct PrefetchRange {
  std::uint64_t first = 0;
  std::uint64_t end = 0;
};
std::optional<PrefetchRange> treelet_prefetch_range(const formats::TreeletMap& map, std::uint64_t block_first,
                                                    std::uint64_t block_bytes, std::uint64_t limit);

// The cache of a direct-mapped treelet prefetcher: one way per set, so every
// policy is the same (a miss replaces the set's block), at a table's cost.
class DirectMappedSlots {
 public:
  static constexpr std::uint64_t kNoSlot = ~std::uint64_t{0};
  explicit DirectMappedSlots(const CacheGeometry& geometry)
      : tags_(geometry.size / geometry.block_size, kNoSlot), mask_(tags_.size() - 1) {}
  bool access(std::uint64_t block, std::uint64_t& slot) {
    slot = block & mask_;
    const bool miss = tags_[slot] != block;
    tags_[slot] = block;
    return miss;
  }
  std::uint64_t place(std::uint64_t block) {
    const std::uint64_t slot = block & mask_;
    if (tags_[slot] == block) return kNoSlot;
    tags_[slot] = block;
    return slot;
  }
  std::uint64_t invalidate_slot(std::uint64_t block) {
    const std::uint64_t slot = block & mask_;
    if (tags_[slot] != block) return kNoSlot;
    tags_[slot] = kNoSlot;
    return slot;
  }
  std::uint64_t slots() const { return tags_.size(); }

 private:
  std::vector<std::uint64_t> tags_;  // kNoSlot when free (block 2^64 - 1 is refused before)
  std::uint64_t mask_;
};

// A cache whose blocks stay in their slots (DirectMappedSlots, PolicyCache)
// with a mark per slot for a block a prefetch placed and no demand fetch has
// used yet.
template <typename Cache>
class SlotMarkedCache {
 public:
  explicit SlotMarkedCache(const CacheGeometry& geometry) : cache_(geometry), unused_(cache_.slots(), 0) {}

  PrefetchDemand demand(std::uint64_t block) {
    std::uint64_t slot = 0;
    if (!cache_.access(block, slot)) [[likely]] {
      if (unused_[slot] == 0) [[likely]] return PrefetchDemand::Hit;
      unused_[slot] = 0;
      return PrefetchDemand::UsefulHit;
    }
    unused_[slot] = 0;
    return PrefetchDemand::Miss;
  }

  // Places `block` as a miss would unless it is resident; true when placed (it is then marked).
  bool prefetch(std::uint64_t block) {
    const std::uint64_t slot = cache_.place(block);
    if (slot == Cache::kNoSlot) return false;
    unused_[slot] = 1;
    return true;
  }

  void invalidate(std::uint64_t block) {
    if (const std::uint64_t slot = cache_.invalidate_slot(block); slot != Cache::kNoSlot) unused_[slot] = 0;
  }

 private:
  Cache cache_;
  std::vector<std::uint8_t> unused_;  // per slot: a prefetched block no demand fetch has used
};

// `MarkedCache`: SlotMarkedCache<DirectMappedSlots> for one way,
// MarkedRecencySets for LRU and FIFO of few ways, else SlotMarkedCache<PolicyCache<...>>.
template <typename MarkedCache>
class TreeletPrefetcher {
 public:
  TreeletPrefetcher(const CacheGeometry& geometry, std::uint64_t limit_bytes)
      : cache_(geometry), shift_(static_cast<unsigned>(std::countr_zero(geometry.block_size))), limit_(limit_bytes) {}

  // A demand fetch; true on a miss, which prefetches the rest of its treelet.
  bool access(std::uint64_t block) {
    const PrefetchDemand demand = cache_.demand(block);
    if (demand == PrefetchDemand::Hit) [[likely]] return false;
    if (demand == PrefetchDemand::UsefulHit) {
      ++counts_.useful;
      return false;
    }
    if (has_map_) prefetch_after(block);
    return true;
  }

  void invalidate(std::uint64_t block) { cache_.invalidate(block); }

  // The animation frame's map (nullptr: the frame has none, nothing is prefetched).
  void begin_treelets(const formats::TreeletMap* map) {
    has_map_ = map != nullptr;
    if (map != nullptr) map_ = *map;
    build_block_ends();
  }

  const PrefetchCounts& prefetch_counts() const { return counts_; }

 private:
  [[gnu::noinline]] void prefetch_after(std::uint64_t block) {
    std::uint64_t end = 0;
    if (!block_ends_.empty()) {
      if (block < first_block_ || block - first_block_ >= block_ends_.size()) return;
      end = block_ends_[block - first_block_];
      if (end == 0) return;
      const std::uint64_t block_first = block << shift_;
      if (limit_ != 0 && end - block_first > limit_) end = block_first + limit_;
    } else {
      const std::optional<PrefetchRange> range =
          treelet_prefetch_range(map_, block << shift_, std::uint64_t{1} << shift_, limit_);
      if (!range) return;
      end = range->end;
    }
    const std::uint64_t last = (end - 1) >> shift_;
    for (std::uint64_t next = block + 1; next <= last; ++next) {
      if (cache_.prefetch(next)) ++counts_.prefetches;
    }
  }

  MarkedCache cache_;
  unsigned shift_;
  std::uint64_t limit_;
  formats::TreeletMap map_;
  bool has_map_ = false;
  // Per block from first_block_: the end of the first treelet that overlaps
  // it (0: none), so a miss reads its treelet's end instead of searching the
  // map; empty when the map spans too many blocks (then it is searched).
  std::vector<std::uint64_t> block_ends_;
  std::uint64_t first_block_ = 0;
  static constexpr std::uint64_t kMostTableBlocks = std::uint64_t{1} << 22;

  void build_block_ends() {
    block_ends_.clear();
    if (!has_map_ || map_.treelets.empty()) return;
    const std::uint64_t first = map_.treelets.front().first >> shift_;
    const formats::TreeletRange& back = map_.treelets.back();
    const std::uint64_t last = (back.first + back.bytes - 1) >> shift_;
    if (last - first >= kMostTableBlocks) return;
    first_block_ = first;
    block_ends_.assign(last - first + 1, 0);
    // Earlier treelets win a block they share with later ones.
    for (auto t = map_.treelets.rbegin(); t != map_.treelets.rend(); ++t) {
      const std::uint64_t end = t->first + t->bytes;
      for (std::uint64_t b = t->first >> shift_; b <= (end - 1) >> shift_; ++b) block_ends_[b - first] = end;
    }
  }
  PrefetchCounts counts_;
};

}  // namespace nodetrace::cachesim
