// Internal: the cache of a treelet prefetcher under LRU or FIFO with few
// ways (at most kScanWays): each set an array of block numbers in recency
// (LRU) or fill (FIFO) order, newest first, as SetAssociativeCache keeps
// them, with a mark per way for a block a prefetch placed and no demand
// fetch has used yet; the mark moves with its block. Misses, evictions and
// marks are those of PolicyCache<RecencyOrder> with a mark per slot, at the
// cost of shifting a few words instead of relinking a list.
#pragma once

#include <cstdint>
#include <vector>

#include "models/prefetch_demand.hpp"
#include "nodetrace/cachesim/models/cache_geometry.hpp"

namespace nodetrace::cachesim {

// `FixedWays`: the ways when known at compile time (the loops then unroll), 0 for any.
template <std::uint32_t FixedWays = 0>
class MarkedRecencySets {
 public:
  explicit MarkedRecencySets(const CacheGeometry& geometry)
      : assoc_(FixedWays != 0 ? FixedWays : geometry.assoc),
        lru_(geometry.replacement == ReplacementPolicy::Lru),
        set_mask_(geometry.size / geometry.block_size / geometry.assoc - 1),
        tags_(geometry.size / geometry.block_size, kInvalid),
        unused_(tags_.size(), 0) {}

  PrefetchDemand demand(std::uint64_t block) {
    const std::uint64_t first = (block & set_mask_) * way_count();
    std::uint64_t* const ways = tags_.data() + first;
    std::uint8_t* const marks = unused_.data() + first;
    if (ways[0] == block) [[likely]] {
      return take_mark(marks[0]);
    }
    return demand_beyond_first(block, ways, marks);
  }

  // Places `block` newest in its set unless it is resident; true when placed (it is then marked).
  bool prefetch(std::uint64_t block) {
    const std::uint64_t first = (block & set_mask_) * way_count();
    std::uint64_t* const ways = tags_.data() + first;
    if (find(ways, block) != way_count()) return false;
    insert(ways, unused_.data() + first, block, 1);
    return true;
  }

  void invalidate(std::uint64_t block) {
    const std::uint64_t first = (block & set_mask_) * way_count();
    std::uint64_t* const ways = tags_.data() + first;
    std::uint8_t* const marks = unused_.data() + first;
    const std::uint32_t way = find(ways, block);
    if (way == way_count()) return;
    for (std::uint32_t next = way + 1; next < way_count(); ++next) {
      ways[next - 1] = ways[next];
      marks[next - 1] = marks[next];
    }
    ways[way_count() - 1] = kInvalid;
    marks[way_count() - 1] = 0;
  }

 private:
  static constexpr std::uint64_t kInvalid = ~std::uint64_t{0};  // block 2^64 - 1 is refused before

  std::uint32_t way_count() const {
    if constexpr (FixedWays != 0) {
      return FixedWays;
    } else {
      return assoc_;
    }
  }

  static PrefetchDemand take_mark(std::uint8_t& mark) {
    if (mark == 0) [[likely]] return PrefetchDemand::Hit;
    mark = 0;
    return PrefetchDemand::UsefulHit;
  }

  std::uint32_t find(const std::uint64_t* ways, std::uint64_t block) const {
    std::uint32_t way = 0;
    while (way < way_count() && ways[way] != block) ++way;
    return way;
  }

  [[gnu::noinline]] PrefetchDemand demand_beyond_first(std::uint64_t block, std::uint64_t* ways,
                                                       std::uint8_t* marks) {
    const std::uint32_t way = find(ways, block);
    if (way == way_count()) {
      insert(ways, marks, block, 0);
      return PrefetchDemand::Miss;
    }
    if (!lru_) return take_mark(marks[way]);
    const std::uint8_t mark = marks[way];
    shift_down(ways, marks, way);
    ways[0] = block;
    marks[0] = 0;
    return mark != 0 ? PrefetchDemand::UsefulHit : PrefetchDemand::Hit;
  }

  // The newest way takes `block`; the oldest (invalid ones are last) leaves.
  void insert(std::uint64_t* ways, std::uint8_t* marks, std::uint64_t block, std::uint8_t mark) {
    shift_down(ways, marks, way_count() - 1);
    ways[0] = block;
    marks[0] = mark;
  }

  // Ways [0, way) move one way older, over `way`. A loop, not std::move_backward,
  // which calls memmove for a handful of words.
  static void shift_down(std::uint64_t* ways, std::uint8_t* marks, std::uint32_t way) {
    for (; way > 0; --way) {
      ways[way] = ways[way - 1];
      marks[way] = marks[way - 1];
    }
  }

  std::uint32_t assoc_;
  bool lru_;
  std::uint64_t set_mask_;
  std::vector<std::uint64_t> tags_;    // per set: newest first, kInvalid after the valid ways
  std::vector<std::uint8_t> unused_;   // per way: a prefetched block no demand fetch has used
};

}  // namespace nodetrace::cachesim
