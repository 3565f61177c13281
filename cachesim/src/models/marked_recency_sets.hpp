// Internal: the cache of a treelet prefetcher under LRU or FIFO with few
// ways (at most kScanWays): each set an array of block numbers in recency
// (LRU) or fill (FIFO) order, newest first, as SetAssociativeCache keeps
// them, with a mark per way for a block a prefetch placed and no demand
// fetch has used yet: bit w of the set's mark word, shifted as its block
// moves. Misses, evictions and marks are those of PolicyCache<RecencyOrder>
// with a mark per slot, at the cost of shifting a few words instead of
// relinking a list.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "models/marked_sets_avx2.hpp"
#include "models/prefetch_demand.hpp"
#include "nodetrace/cachesim/models/cache_geometry.hpp"

namespace nodetrace::cachesim {

// `FixedWays`: the ways when known at compile time (the loops then unroll), 0 for any.
template <std::uint32_t FixedWays = 0>
class MarkedRecencySets {
  static constexpr bool kVectorWays = FixedWays == 4 || FixedWays == 8;

 public:
  // `use_avx2`: demand and prefetch runs take the AVX2 forms where the
  // processor has it (4 and 8 ways); false keeps the scalar ones (tests
  // compare the two).
  explicit MarkedRecencySets(const CacheGeometry& geometry, bool use_avx2 = true)
      : assoc_(FixedWays != 0 ? FixedWays : geometry.assoc),
        lru_(geometry.replacement == ReplacementPolicy::Lru),
        avx2_(kVectorWays && use_avx2 && cpu_has_avx2()),
        set_mask_(geometry.size / geometry.block_size / geometry.assoc - 1),
        tags_(geometry.size / geometry.block_size, kInvalid),
        marks_(set_mask_ + 1, 0) {}

  // Whether demand and prefetch runs take the AVX2 forms.
  bool vector_runs() const { return avx2_; }

  PrefetchDemand demand(std::uint64_t block) {
    const std::uint64_t set = block & set_mask_;
    return demand_in(tags_.data() + set * way_count(), marks_[set], block);
  }

  // demand() of `count` blocks, block_at(i) the i-th, adding the useful
  // hits to `useful` and calling on_miss(block) after each miss; returns the
  // misses. The arrays and the mask stay in registers through the loop,
  // where a caller's loop of demand() reloads them after every store.
  template <typename BlockAt, typename OnMiss>
  std::uint64_t demand_run(std::size_t count, BlockAt block_at, std::uint64_t& useful, OnMiss on_miss) {
#if defined(NODETRACE_MARKED_SETS_AVX2)  // the AVX2 forms exist on x86-64 only
    if constexpr (kVectorWays) {
      if (avx2_) {
        const auto run = lru_ ? demand_run_avx2<FixedWays, true, BlockAt, OnMiss>
                              : demand_run_avx2<FixedWays, false, BlockAt, OnMiss>;
        return run(tags_.data(), marks_.data(), set_mask_, count, block_at, useful, on_miss);
      }
    }
#endif
    std::uint64_t* const tags = tags_.data();
    std::uint32_t* const marks = marks_.data();
    const std::uint64_t set_mask = set_mask_;
    std::uint64_t misses = 0;
    std::uint64_t used = 0;
    for (std::size_t i = 0; i < count; ++i) {
      const std::uint64_t block = block_at(i);
      const std::uint64_t set = block & set_mask;
      const PrefetchDemand demand = demand_in(tags + set * way_count(), marks[set], block);
      if (demand == PrefetchDemand::Hit) [[likely]] continue;
      if (demand == PrefetchDemand::UsefulHit) {
        ++used;
        continue;
      }
      ++misses;
      on_miss(block);
    }
    useful += used;
    return misses;
  }

  // Places each block from `first` to `last` newest in its set, marked,
  // unless it is resident; returns how many were placed.
  std::uint64_t prefetch_run(std::uint64_t first, std::uint64_t last) {
#if defined(NODETRACE_MARKED_SETS_AVX2)
    if constexpr (kVectorWays) {
      if (avx2_) return prefetch_run_avx2<FixedWays>(tags_.data(), marks_.data(), set_mask_, first, last);
    }
#endif
    // Locals: stores through the arrays cannot change them.
    std::uint64_t* const tags = tags_.data();
    std::uint32_t* const marks = marks_.data();
    const std::uint64_t set_mask = set_mask_;
    const std::uint32_t all_ways = all_ways_mask();
    std::uint64_t placed = 0;
    for (std::uint64_t block = first;; ++block) {
      const std::uint64_t set = block & set_mask;
      std::uint64_t* const ways = tags + set * way_count();
      if (find(ways, block) == way_count()) {
        shift_down(ways, way_count() - 1);
        ways[0] = block;
        marks[set] = ((marks[set] << 1) | 1) & all_ways;
        ++placed;
      }
      if (block == last) return placed;
    }
  }

  void invalidate(std::uint64_t block) {
    const std::uint64_t set = block & set_mask_;
    std::uint64_t* const ways = tags_.data() + set * way_count();
    const std::uint32_t way = find(ways, block);
    if (way == way_count()) return;
    for (std::uint32_t next = way + 1; next < way_count(); ++next) ways[next - 1] = ways[next];
    ways[way_count() - 1] = kInvalid;
    // The marks above `way` move one way newer, over it; the last way's is 0.
    const std::uint32_t below = (std::uint32_t{1} << way) - 1;
    marks_[set] = (marks_[set] & below) | ((marks_[set] >> 1) & ~below & (all_ways_mask() >> 1));
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

  // Bits 0 to ways - 1 (ways at most 16).
  std::uint32_t all_ways_mask() const { return (std::uint32_t{1} << way_count()) - 1; }

  std::uint32_t find(const std::uint64_t* ways, std::uint64_t block) const {
    std::uint32_t way = 0;
    while (way < way_count() && ways[way] != block) ++way;
    return way;
  }

  // A demand fetch of `block` in the set of `ways` and `marks`.
  [[gnu::always_inline]] PrefetchDemand demand_in(std::uint64_t* ways, std::uint32_t& marks, std::uint64_t block) {
    if (ways[0] == block) [[likely]] {
      if ((marks & 1) == 0) [[likely]] return PrefetchDemand::Hit;
      marks &= ~std::uint32_t{1};
      return PrefetchDemand::UsefulHit;
    }
    const std::uint32_t way = find(ways, block);
    if (way == way_count()) {
      shift_down(ways, way_count() - 1);
      ways[0] = block;
      marks = (marks << 1) & all_ways_mask();
      return PrefetchDemand::Miss;
    }
    const std::uint32_t bit = std::uint32_t{1} << way;
    const bool marked = (marks & bit) != 0;
    if (!lru_) {
      marks &= ~bit;
    } else {
      // Ways [0, way) move one way older, over `way`; way 0 takes the block, unmarked.
      shift_down(ways, way);
      ways[0] = block;
      const std::uint32_t through = (bit << 1) - 1;
      marks = (marks & ~through) | ((marks << 1) & through & ~std::uint32_t{1});
    }
    return marked ? PrefetchDemand::UsefulHit : PrefetchDemand::Hit;
  }

  // Ways [0, way) move one way older, over `way`. Not a plain loop, which
  // GCC turns into a call of memmove for a handful of words: unrolled when
  // the ways are fixed, else a loop whose counter the compiler cannot see.
  static void shift_down(std::uint64_t* ways, std::uint32_t way) {
    if constexpr (FixedWays != 0) {
      for (std::uint32_t w = FixedWays - 1; w > 0; --w) {
        if (w <= way) ways[w] = ways[w - 1];
      }
    } else {
      for (; way > 0; --way) {
        asm("" : "+r"(way));
        ways[way] = ways[way - 1];
      }
    }
  }

  std::uint32_t assoc_;
  bool lru_;
  bool avx2_;
  std::uint64_t set_mask_;
  std::vector<std::uint64_t> tags_;   // per set: newest first, kInvalid after the valid ways
  std::vector<std::uint32_t> marks_;  // per set: bit w, a prefetched block in way w no demand fetch has used
};

}  // namespace nodetrace::cachesim
