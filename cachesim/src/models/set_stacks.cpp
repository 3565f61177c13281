#include "nodetrace/cachesim/models/set_stacks.hpp"

#include <algorithm>
#include <stdexcept>

#include "models/set_stack_run.hpp"

namespace nodetrace::cachesim {

SetStacks::SetStacks(std::vector<Level> levels, bool by_tag) : by_tag_(by_tag) {
  std::sort(levels.begin(), levels.end(),
            [](const Level& a, const Level& b) { return a.log2_sets < b.log2_sets; });
  for (const Level& level : levels) {
    if (level.depth == 0) throw std::invalid_argument("SetStacks: a depth of 0");
  }
  std::size_t slots = 0;
  std::size_t counts = 0;
  for (const Level& level : levels) {
    slots += (std::size_t{1} << level.log2_sets) * level.depth;
    counts += level.depth + 1;
  }
  storage_.assign(slots, kEmpty);
  counts_.assign(counts, 0);
  std::size_t slot = 0;
  std::size_t count = 0;
  for (const Level& level : levels) {
    LevelState state;
    state.stacks = storage_.data() + slot;
    state.mask = (std::uint64_t{1} << level.log2_sets) - 1;
    state.depth = level.depth;
    state.deeper = counts_.data() + count;
    state.log2_sets = level.log2_sets;
    slot += (std::size_t{1} << level.log2_sets) * level.depth;
    count += level.depth + 1;
    levels_.push_back(std::move(state));
  }
  for (const LevelState& level : levels_) direct_mapped_ = direct_mapped_ && level.depth == 1;
}

void SetStacks::access_blocks(const std::uint64_t* blocks, std::size_t count) {
  fetches_ += count;
  if (passed_.size() < count) passed_.resize(count);
  // Each set count passes on what it did not find on top, in place.
  const std::uint64_t* in = blocks;
  std::uint64_t* const passed = passed_.data();
  for (LevelState& level : levels_) {
    switch (level.depth) {
      case 1: count = run_set_stacks<1>(level.stacks, level.mask, in, count, passed, level.deeper); break;
      case 2: count = run_set_stacks<2>(level.stacks, level.mask, in, count, passed, level.deeper); break;
      case 4: count = run_set_stacks<4>(level.stacks, level.mask, in, count, passed, level.deeper); break;
      case 8: count = run_set_stacks<8>(level.stacks, level.mask, in, count, passed, level.deeper); break;
      case 16: count = run_set_stacks<16>(level.stacks, level.mask, in, count, passed, level.deeper); break;
      default:
        count = run_set_stacks_any(level.stacks, level.mask, level.depth, in, count, passed, level.deeper);
    }
    in = passed;
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
  const std::uint64_t* const stack = at.stacks + (set & at.mask) * at.depth;
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
