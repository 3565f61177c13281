// Hill and Smith's all-associativity simulation: one structure answers every
// LRU cache of one block size whose set count is one of the given powers of
// two and whose ways are at most that set count's depth. Each set count
// keeps per-set LRU stacks (most recent first) as deep as its largest
// associativity; a fetch misses in a cache of W ways exactly when its block
// is not among the W most recent blocks of its set.
//
// Set counts are walked from the fewest sets up and the walk stops at the
// first set count where the block is already on top of its set: with bit
// selection every set of a larger set count is part of a set of a smaller
// one, so the block is on top there too and nothing changes (the "forest"
// of direct-mapped caches is the case of depth 1 everywhere).
//
// Stacks of 1, 2, 4 or 8 places start narrow (narrow_set_stack_run.hpp:
// 32-bit blocks, half the work) and are widened to 64-bit blocks before the
// first block that needs more than 32 bits: the counts are the same either
// way.
//
// No invalidation: removing a block breaks the inclusion between
// associativities (a W-way cache then holds a free way that a W+1-way cache
// fills); a caller with invalidates hands over to per-cache simulation, the
// stacks giving each cache's contents (ways_of).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "nodetrace/formats/record/record.hpp"

namespace nodetrace::cachesim {

class SetStacks {
 public:
  static constexpr std::uint64_t kEmpty = ~std::uint64_t{0};

  struct Level {
    unsigned log2_sets = 0;
    std::uint32_t depth = 1;  // the largest associativity asked of this set count
  };

  // `levels`: distinct set counts, any order; `by_tag`: misses are also
  // counted by the fetch's tag (--per-level).
  explicit SetStacks(std::vector<Level> levels, bool by_tag = false);

  // One demand fetch of `block`; `tag` is counted only with by_tag.
  void access(std::uint64_t block, unsigned tag = 0);

  // Every level one block deep (direct-mapped caches only)?
  bool direct_mapped() const { return direct_mapped_; }
  // access() of each block in turn (no counts by tag), set count by set
  // count: each one's stacks run over the fetches the one before it did
  // not find on top, so its stacks stay in the processor's cache for all
  // of them and no branch depends on where a block was found.
  void access_blocks(const std::uint64_t* blocks, std::size_t count);
  // access_blocks() of the blocks of `count` records, each one demand
  // fetch of the block its address shifted right by `shift` gives: the
  // first set count reads the records themselves (no copy of the blocks).
  void access_records(const formats::Record* records, std::size_t count, unsigned shift);

  // Some fetches of a chunk, in order: at least every one whose block was
  // not the last one its set fetched, with 2^log2_sets sets (a policy
  // grid's filters keep these: policy_grid.hpp).
  struct Filtered {
    unsigned log2_sets = 0;
    const std::uint64_t* blocks = nullptr;
    std::size_t count = 0;
  };
  // access_records(), but each set count walks the shortest list known to
  // hold every fetch that reaches it: the records, what the set count
  // before it passed on, or the one of `filtered` (fewest sets first) with
  // the most sets not above its own and above the set count before's. A
  // fetch left out is on top of its set there, so on top, and changing
  // nothing, in every larger set count. `fit_32_bits`: every block of the
  // records is below 2^32 - 1 (blocks_fit_32_bits), known to the caller.
  void access_records_filtered(const formats::Record* records, std::size_t count, unsigned shift,
                               std::span<const Filtered> filtered, bool fit_32_bits);

  std::uint64_t fetches() const { return fetches_; }
  // Misses of the cache with 2^log2_sets sets and `ways` ways (ways <= its
  // level's depth); with `tag`, of that tag's fetches only.
  std::uint64_t misses(unsigned log2_sets, std::uint32_t ways) const;
  std::uint64_t misses(unsigned log2_sets, std::uint32_t ways, unsigned tag) const;
  // The `ways` most recent blocks of set `set` (kEmpty where the set holds
  // fewer), most recent first: the contents of that LRU cache.
  std::vector<std::uint64_t> ways_of(unsigned log2_sets, std::uint64_t set,
                                     std::uint32_t ways) const;

  // What access()'s walk (or access_blocks()) did at one set count so
  // far: the fetches that reached
  // it, and the places they searched and moved down there (a block found at
  // place p moves p blocks; one not kept, depth - 1). A sweep weighs the
  // set counts' work by these to share them out among threads.
  struct Walk {
    std::uint64_t visits = 0;
    std::uint64_t places = 0;
  };
  Walk walk(unsigned log2_sets) const;

 private:
  struct LevelState {
    std::uint64_t* stacks = nullptr;  // wide: depth blocks a set, most recent first
    std::uint32_t* narrow_stacks = nullptr;  // narrow (stacks null): the same with 32-bit blocks
    std::uint64_t mask = 0;
    std::uint32_t depth = 1;
    // deeper[p]: fetches found at 0-based place p >= 1 (p = depth: not
    // kept); those at place 0 stopped the walk at or before this level.
    std::uint64_t* deeper = nullptr;
    std::vector<std::uint64_t> deeper_by_tag;  // [tag * (depth + 1) + p], by_tag only
    unsigned log2_sets = 0;
  };
  const LevelState& level(unsigned log2_sets) const;
  static void count_tag(LevelState& level, unsigned tag, std::uint32_t position);
  // Every narrow level to wide stacks, keeping each set's order.
  void widen();
  // The levels from `from` on over `count` fetches, `in` the first one's
  // blocks (which may be passed_) and passed_ the others'.
  void run_levels(std::size_t from, const std::uint64_t* in, std::size_t count);
  // One set count over `count` fetches into passed_ (`in` may be passed_);
  // returns how many it passed on.
  std::size_t run_level(LevelState& level, const std::uint64_t* in, std::size_t count);
  // The first set count over the records' blocks into passed_.
  std::size_t run_first_level(const formats::Record* records, std::size_t count, unsigned shift);

  std::vector<LevelState> levels_;
  std::vector<std::uint64_t> storage_;  // the wide levels' stacks
  std::vector<std::uint32_t> narrow_storage_;  // the narrow levels' stacks
  std::vector<std::uint64_t> widened_;         // the same once widened
  bool narrow_ = false;                 // some levels are narrow
  std::vector<std::uint64_t> counts_;
  std::vector<std::uint64_t> passed_;  // access_blocks()' fetches not on top so far
  std::uint64_t fetches_ = 0;
  bool by_tag_ = false;
  bool direct_mapped_ = true;
};

}  // namespace nodetrace::cachesim
