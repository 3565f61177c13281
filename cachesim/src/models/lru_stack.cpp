#include "nodetrace/cachesim/models/lru_stack.hpp"

#include <algorithm>
#include <bit>
#include <utility>

namespace nodetrace::cachesim {

std::uint64_t LruStack::access(std::uint64_t block) {
  if (now_ + 1 >= tree_.size()) renumber();
  ++now_;
  const auto [entry, first] = last_.try_emplace(block, now_);
  std::uint64_t position = 0;
  if (!first) {
    const std::uint64_t before = entry->second;
    // Stamps after `before` are the distinct blocks referenced since.
    position = static_cast<std::uint64_t>(last_.size()) - prefix(before) + 1;
    add(before, -1);
    entry->second = now_;
  }
  add(now_, +1);
  return position;
}

// Times grow without bound; when the tree is full, the live stamps (one per
// block) are renumbered 1..n in their order and the tree rebuilt larger.
void LruStack::renumber() {
  std::vector<std::pair<std::uint64_t, std::uint64_t>> live;  // time, block
  live.reserve(last_.size());
  for (const auto& [block, time] : last_) live.emplace_back(time, block);
  std::sort(live.begin(), live.end());
  const std::uint64_t size = std::max<std::uint64_t>(1 << 16, 4 * (live.size() + 1));
  tree_.assign(size, 0);
  now_ = 0;
  for (const auto& [time, block] : live) {
    last_[block] = ++now_;
    tree_[now_] += 1;
  }
  // Linear Fenwick build.
  for (std::uint64_t i = 1; i < size; ++i) {
    const std::uint64_t parent = i + (i & (~i + 1));
    if (parent < size) tree_[parent] += tree_[i];
  }
}

void LruStack::add(std::uint64_t time, int delta) {
  for (std::uint64_t i = time; i < tree_.size(); i += i & (~i + 1)) tree_[i] += delta;
}

std::uint64_t LruStack::prefix(std::uint64_t time) const {
  std::int64_t sum = 0;
  for (std::uint64_t i = time; i > 0; i -= i & (~i + 1)) sum += tree_[i];
  return static_cast<std::uint64_t>(sum);
}

void LruSizeCurve::count(std::uint64_t position) {
  ++references_;
  if (position == 0) {
    ++first_;
  } else {
    ++by_bucket_[static_cast<unsigned>(std::bit_width(position - 1))];
  }
}

std::uint64_t LruSizeCurve::misses(unsigned log2_blocks) const {
  std::uint64_t misses = first_;
  for (std::size_t bucket = log2_blocks + 1; bucket < by_bucket_.size(); ++bucket) {
    misses += by_bucket_[bucket];
  }
  return misses;
}

}  // namespace nodetrace::cachesim
