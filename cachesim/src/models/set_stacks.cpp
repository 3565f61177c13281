#include "nodetrace/cachesim/models/set_stacks.hpp"

#include <algorithm>
#include <stdexcept>

#include "models/narrow_set_stack_run.hpp"
#include "models/record_blocks.hpp"
#include "models/set_stack_run.hpp"

namespace nodetrace::cachesim {

namespace {

bool narrow_depth(std::uint32_t depth) { return depth == 1 || depth == 2 || depth == 4 || depth == 8; }

}  // namespace

SetStacks::SetStacks(std::vector<Level> levels, bool by_tag) : by_tag_(by_tag) {
  std::sort(levels.begin(), levels.end(),
            [](const Level& a, const Level& b) { return a.log2_sets < b.log2_sets; });
  for (const Level& level : levels) {
    if (level.depth == 0) throw std::invalid_argument("SetStacks: a depth of 0");
  }
  std::size_t slots = 0;
  std::size_t narrow_slots = 0;
  std::size_t counts = 0;
  for (const Level& level : levels) {
    const std::size_t sets = std::size_t{1} << level.log2_sets;
    (narrow_depth(level.depth) ? narrow_slots : slots) += sets * level.depth;
    counts += level.depth + 1;
  }
  storage_.assign(slots, kEmpty);
  narrow_storage_.assign(narrow_slots, kNarrowEmpty);
  counts_.assign(counts, 0);
  std::size_t slot = 0;
  std::size_t narrow_slot = 0;
  std::size_t count = 0;
  for (const Level& level : levels) {
    const std::size_t sets = std::size_t{1} << level.log2_sets;
    LevelState state;
    if (narrow_depth(level.depth)) {
      state.narrow_stacks = narrow_storage_.data() + narrow_slot;
      narrow_slot += sets * level.depth;
      narrow_ = true;
    } else {
      state.stacks = storage_.data() + slot;
      slot += sets * level.depth;
    }
    state.mask = sets - 1;
    state.depth = level.depth;
    state.deeper = counts_.data() + count;
    state.log2_sets = level.log2_sets;
    count += level.depth + 1;
    levels_.push_back(std::move(state));
  }
  for (const LevelState& level : levels_) direct_mapped_ = direct_mapped_ && level.depth == 1;
}

void SetStacks::widen() {
  widened_.resize(narrow_storage_.size());
  std::transform(narrow_storage_.begin(), narrow_storage_.end(), widened_.begin(),
                 [](std::uint32_t block) { return block == kNarrowEmpty ? kEmpty : block; });
  for (LevelState& level : levels_) {
    if (!level.narrow_stacks) continue;
    level.stacks = widened_.data() + (level.narrow_stacks - narrow_storage_.data());
    level.narrow_stacks = nullptr;
  }
  narrow_ = false;
  narrow_storage_ = {};
}

void SetStacks::access(std::uint64_t block, unsigned tag) {
  if (narrow_ && !fits_narrow(block)) widen();
  ++fetches_;
  for (LevelState& level : levels_) {
    std::uint32_t position;
    if (level.narrow_stacks) {
      const auto narrow = static_cast<std::uint32_t>(block);
      std::uint32_t* const set = level.narrow_stacks + (block & level.mask) * level.depth;
      switch (level.depth) {
        case 1: position = narrow_access<1>(set, narrow); break;
        case 2: position = narrow_access<2>(set, narrow); break;
        case 4: position = narrow_access<4>(set, narrow); break;
        default: position = narrow_access<8>(set, narrow);
      }
      if (position == 0) return;  // on top here, so on top of every larger set count
    } else {
      std::uint64_t* const set = level.stacks + (block & level.mask) * level.depth;
      if (set[0] == block) return;
      // position: 0-based place found, or depth when not among the kept
      // ones (then the oldest kept block falls off). Measured: this plain
      // loop is faster than a branchless move-to-front.
      position = 1;
      while (position < level.depth && set[position] != block) ++position;
      const std::uint32_t moved = position < level.depth ? position : level.depth - 1;
      for (std::uint32_t i = moved; i > 0; --i) set[i] = set[i - 1];
      set[0] = block;
    }
    ++level.deeper[position];
    if (by_tag_) count_tag(level, tag, position);
  }
}

namespace {

// One narrow set count's run over `count` fetches (`in`: blocks or a view
// of them) into `out`; returns how many it passed on.
template <typename In>
std::size_t run_narrow_level(std::uint32_t* stacks, std::uint64_t mask, unsigned depth, In in, std::size_t count,
                             std::uint64_t* out, std::uint64_t* deeper) {
  switch (depth) {
    case 1: return run_narrow_set_stacks<1>(stacks, mask, in, count, out, deeper);
    case 2: return run_narrow_set_stacks<2>(stacks, mask, in, count, out, deeper);
    case 4: return run_narrow_set_stacks<4>(stacks, mask, in, count, out, deeper);
    default: return run_narrow_set_stacks_of_8(stacks, mask, in, count, out, deeper);
  }
}

}  // namespace

void SetStacks::access_blocks(const std::uint64_t* blocks, std::size_t count) {
  // Widened before the batch when any block in it needs more than 32 bits:
  // the stacks so far saw only blocks that fit.
  if (narrow_ && !blocks_fit_32_bits(blocks, count)) widen();
  fetches_ += count;
  if (passed_.size() < count) passed_.resize(count);
  run_levels(0, blocks, count);
}

void SetStacks::access_records(const formats::Record* records, std::size_t count, unsigned shift) {
  if (narrow_ && !blocks_fit_32_bits(RecordBlocks{records, shift}, count)) widen();
  fetches_ += count;
  if (levels_.empty()) return;
  if (passed_.size() < count) passed_.resize(count);
  run_levels(1, passed_.data(), run_first_level(records, count, shift));
}

void SetStacks::access_records_filtered(const formats::Record* records, std::size_t count, unsigned shift,
                                        std::span<const Filtered> filtered, bool fit_32_bits) {
  if (narrow_ && !fit_32_bits) widen();
  fetches_ += count;
  if (passed_.size() < count) passed_.resize(count);
  std::size_t next = 0;    // the first of `filtered` no set count has looked at
  std::size_t passed = 0;  // by the set count before
  for (std::size_t l = 0; l < levels_.size(); ++l) {
    LevelState& level = levels_[l];
    const Filtered* nearest = nullptr;
    while (next < filtered.size() && filtered[next].log2_sets <= level.log2_sets) nearest = &filtered[next++];
    // A list of no more sets than the set count before is no shorter than
    // what that one passed on.
    if (nearest != nullptr && (l == 0 || nearest->log2_sets > levels_[l - 1].log2_sets)) {
      passed = run_level(level, nearest->blocks, nearest->count);
    } else if (l == 0) {
      passed = run_first_level(records, count, shift);
    } else {
      passed = run_level(level, passed_.data(), passed);
    }
  }
}

std::size_t SetStacks::run_first_level(const formats::Record* records, std::size_t count, unsigned shift) {
  const RecordBlocks blocks{records, shift};
  LevelState& first = levels_.front();
  if (first.narrow_stacks != nullptr) {
    return run_narrow_level(first.narrow_stacks, first.mask, first.depth, blocks, count, passed_.data(), first.deeper);
  }
  // A wide first set count: its runs read blocks.
  for (std::size_t i = 0; i < count; ++i) passed_[i] = blocks[i];
  return run_level(first, passed_.data(), count);
}

void SetStacks::run_levels(std::size_t from, const std::uint64_t* in, std::size_t count) {
  // Each set count passes on what it did not find on top, in place.
  for (std::size_t l = from; l < levels_.size(); ++l) {
    count = run_level(levels_[l], in, count);
    in = passed_.data();
  }
}

std::size_t SetStacks::run_level(LevelState& level, const std::uint64_t* in, std::size_t count) {
  std::uint64_t* const passed = passed_.data();
  if (level.narrow_stacks != nullptr) {
    return run_narrow_level(level.narrow_stacks, level.mask, level.depth, in, count, passed, level.deeper);
  }
  switch (level.depth) {
    case 1: return run_set_stacks<1>(level.stacks, level.mask, in, count, passed, level.deeper);
    case 2: return run_set_stacks<2>(level.stacks, level.mask, in, count, passed, level.deeper);
    case 4: return run_set_stacks<4>(level.stacks, level.mask, in, count, passed, level.deeper);
    case 8: return run_set_stacks<8>(level.stacks, level.mask, in, count, passed, level.deeper);
    case 16: return run_set_stacks<16>(level.stacks, level.mask, in, count, passed, level.deeper);
    default: return run_set_stacks_any(level.stacks, level.mask, level.depth, in, count, passed, level.deeper);
  }
}

void SetStacks::count_tag(LevelState& level, unsigned tag, std::uint32_t position) {
  const std::size_t at = std::size_t{tag} * (level.depth + 1) + position;
  if (at >= level.deeper_by_tag.size()) {
    level.deeper_by_tag.resize((std::size_t{tag} + 1) * (level.depth + 1), 0);
  }
  ++level.deeper_by_tag[at];
}

const SetStacks::LevelState& SetStacks::level(unsigned log2_sets) const {
  for (const LevelState& level : levels_) {
    if (level.log2_sets == log2_sets) return level;
  }
  throw std::logic_error("SetStacks: no such set count");
}

std::uint64_t SetStacks::misses(unsigned log2_sets, std::uint32_t ways) const {
  const LevelState& at = level(log2_sets);
  std::uint64_t misses = 0;
  for (std::uint32_t place = ways; place <= at.depth; ++place) misses += at.deeper[place];
  return misses;
}

std::uint64_t SetStacks::misses(unsigned log2_sets, std::uint32_t ways, unsigned tag) const {
  const LevelState& at = level(log2_sets);
  std::uint64_t misses = 0;
  const std::size_t base = std::size_t{tag} * (at.depth + 1);
  for (std::uint32_t place = ways; place <= at.depth; ++place) {
    if (base + place < at.deeper_by_tag.size()) misses += at.deeper_by_tag[base + place];
  }
  return misses;
}

std::vector<std::uint64_t> SetStacks::ways_of(unsigned log2_sets, std::uint64_t set,
                                              std::uint32_t ways) const {
  const LevelState& at = level(log2_sets);
  set &= at.mask;
  if (at.narrow_stacks) {
    const std::uint32_t* const stack = at.narrow_stacks + set * at.depth;
    std::vector<std::uint64_t> blocks(ways);
    std::transform(stack, stack + ways, blocks.begin(),
                   [](std::uint32_t block) { return block == kNarrowEmpty ? kEmpty : block; });
    return blocks;
  }
  const std::uint64_t* const stack = at.stacks + set * at.depth;
  return std::vector<std::uint64_t>(stack, stack + ways);
}

SetStacks::Walk SetStacks::walk(unsigned log2_sets) const {
  Walk walk;
  walk.visits = fetches_;
  for (const LevelState& at : levels_) {
    if (at.log2_sets == log2_sets) {
      for (std::uint32_t place = 1; place <= at.depth; ++place) {
        walk.places += at.deeper[place] * std::min(place, at.depth - 1);
      }
      return walk;
    }
    // A fetch goes on past a set count where it was not on top.
    walk.visits = 0;
    for (std::uint32_t place = 1; place <= at.depth; ++place) walk.visits += at.deeper[place];
  }
  throw std::logic_error("SetStacks: no such set count");
}

}  // namespace nodetrace::cachesim
