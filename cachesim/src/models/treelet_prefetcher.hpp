// Internal: a cache that prefetches treelets (`cachesim run --prefetch
// treelet`, nodetrace/cachesim/sweep/treelet_prefetch.hpp). A cache of any
// policy but opt (a PolicyCache, or MarkedRecencySets for LRU and FIFO of
// few ways), with a mark per block that a prefetch placed and no demand
// fetch has used yet: a demand hit on a marked block is
// a useful prefetch. Prefetched blocks enter as the policy inserts a missed
// one (LRU: most recent; FIFO, random: newest filled; PLRU: the tree points
// away; RRIP: the insertion value, counting towards BRRIP's every 32nd).
#pragma once

#include <algorithm>
#include <cstdint>
#include <limits>
#include <optional>
#include <type_traits>
#include <vector>

#include "models/policy_cache.hpp"
#include "models/prefetch_demand.hpp"
#include "nodetrace/cachesim/sweep/treelet_prefetch.hpp"
#include "nodetrace/formats/container/treelet_map.hpp"
#include "nodetrace/formats/record/record.hpp"

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
  std::uint64_t* tags() { return tags_.data(); }
  std::uint64_t mask() const { return mask_; }

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

  // demand() of `count` blocks, as MarkedRecencySets::demand_run, for a
  // direct-mapped table: its arrays and mask stay in registers through the loop.
  template <typename BlockAt, typename OnMiss>
  std::uint64_t demand_run(std::size_t count, BlockAt block_at, std::uint64_t& useful, OnMiss on_miss)
    requires std::is_same_v<Cache, DirectMappedSlots>
  {
    std::uint64_t* const tags = cache_.tags();
    std::uint8_t* const unused = unused_.data();
    const std::uint64_t mask = cache_.mask();
    std::uint64_t misses = 0;
    std::uint64_t used = 0;
    for (std::size_t i = 0; i < count; ++i) {
      const std::uint64_t block = block_at(i);
      const std::uint64_t slot = block & mask;
      if (tags[slot] == block) [[likely]] {
        if (unused[slot] != 0) {
          unused[slot] = 0;
          ++used;
        }
        continue;
      }
      tags[slot] = block;
      unused[slot] = 0;
      ++misses;
      on_miss(block);
    }
    useful += used;
    return misses;
  }

  // Places `block` as a miss would unless it is resident; true when placed (it is then marked).
  bool prefetch(std::uint64_t block) {
    const std::uint64_t slot = cache_.place(block);
    if (slot == Cache::kNoSlot) return false;
    unused_[slot] = 1;
    return true;
  }

  // prefetch() of each block from `first` to `last`; returns how many were placed.
  std::uint64_t prefetch_run(std::uint64_t first, std::uint64_t last) {
    std::uint64_t placed = 0;
    if constexpr (std::is_same_v<Cache, DirectMappedSlots>) {
      // The arrays and mask in registers, as in demand_run.
      std::uint64_t* const tags = cache_.tags();
      std::uint8_t* const unused = unused_.data();
      const std::uint64_t mask = cache_.mask();
      for (std::uint64_t block = first;; ++block) {
        const std::uint64_t slot = block & mask;
        if (tags[slot] != block) {
          tags[slot] = block;
          unused[slot] = 1;
          ++placed;
        }
        if (block == last) return placed;
      }
    } else {
      for (std::uint64_t block = first;; ++block) {
        placed += prefetch(block);
        if (block == last) return placed;
      }
    }
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
      : cache_(geometry),
        shift_(static_cast<unsigned>(std::countr_zero(geometry.block_size))),
        limit_(limit_bytes),
        limit_blocks_(limit_bytes != 0 ? (limit_bytes - 1) >> shift_ : ~std::uint64_t{0}) {}

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

  // access() of the block of each of `count` records (address >> `shift`);
  // returns the misses. One loop here keeps the cache's arrays and mask in
  // registers, where the caller's loop reloads them after every store.
  std::uint64_t access_blocks_of(const formats::Record* records, std::size_t count, unsigned shift) {
    const auto block_at = [records, shift](std::size_t i) { return records[i].address >> shift; };
    if constexpr (requires { cache_.demand_run(count, block_at, counts_.useful, [](std::uint64_t) {}); }) {
      return cache_.demand_run(count, block_at, counts_.useful, [this](std::uint64_t block) {
        if (has_map_) prefetch_after(block);
      });
    } else {
      std::uint64_t misses = 0;
      for (std::size_t i = 0; i < count; ++i) misses += access(block_at(i));
      return misses;
    }
  }

  // The animation frame's map (nullptr: the frame has none, nothing is prefetched).
  void begin_treelets(const formats::TreeletMap* map) {
    has_map_ = map != nullptr;
    if (map != nullptr) map_ = *map;
    build_blocks_after();
  }

  const PrefetchCounts& prefetch_counts() const { return counts_; }

 private:
  [[gnu::noinline]] void prefetch_after(std::uint64_t block) {
    std::uint64_t last = block;
    if (!blocks_after_.empty()) {
      if (block < first_block_ || block - first_block_ >= blocks_after_.size()) return;
      // The limit counts bytes from the block's first, a multiple of the block size.
      last = block + std::min<std::uint64_t>(blocks_after_[block - first_block_], limit_blocks_);
    } else {
      const std::optional<PrefetchRange> range =
          treelet_prefetch_range(map_, block << shift_, std::uint64_t{1} << shift_, limit_);
      if (!range) return;
      last = (range->end - 1) >> shift_;
    }
    if (last > block) counts_.prefetches += cache_.prefetch_run(block + 1, last);
  }

  MarkedCache cache_;
  unsigned shift_;
  std::uint64_t limit_;
  // The blocks after the missed one that the limit leaves (all without one).
  std::uint64_t limit_blocks_;
  formats::TreeletMap map_;
  bool has_map_ = false;
  // Per block from first_block_: how many blocks follow it to the last of
  // the first treelet that overlaps it (0 also where none does), so a miss
  // reads its run instead of searching the map. Two bytes a block keep the
  // table small enough to stay in the processor's caches (a miss reads it at
  // a random place). Empty when the map spans too many blocks or a treelet
  // 2^16 blocks or more (then it is searched).
  std::vector<std::uint16_t> blocks_after_;
  std::uint64_t first_block_ = 0;
  static constexpr std::uint64_t kMostTableBlocks = std::uint64_t{1} << 22;

  void build_blocks_after() {
    blocks_after_.clear();
    if (!has_map_ || map_.treelets.empty()) return;
    const std::uint64_t first = map_.treelets.front().first >> shift_;
    const formats::TreeletRange& back = map_.treelets.back();
    const std::uint64_t last = (back.first + back.bytes - 1) >> shift_;
    if (last - first >= kMostTableBlocks) return;
    const auto too_long = [this](const formats::TreeletRange& t) {
      return ((t.first + t.bytes - 1) >> shift_) - (t.first >> shift_) > std::numeric_limits<std::uint16_t>::max();
    };
    if (std::any_of(map_.treelets.begin(), map_.treelets.end(), too_long)) return;
    first_block_ = first;
    blocks_after_.assign(last - first + 1, 0);
    // Earlier treelets win a block they share with later ones.
    for (auto t = map_.treelets.rbegin(); t != map_.treelets.rend(); ++t) {
      const std::uint64_t treelet_last = (t->first + t->bytes - 1) >> shift_;
      for (std::uint64_t b = t->first >> shift_; b <= treelet_last; ++b) {
        blocks_after_[b - first] = static_cast<std::uint16_t>(treelet_last - b);
      }
    }
  }
  PrefetchCounts counts_;
};

}  // namespace nodetrace::cachesim
