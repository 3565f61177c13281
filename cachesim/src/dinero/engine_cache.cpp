// One simulated cache: the reference algorithm of Dinero IV's d4ref, written
// afresh around flat arrays. See engine_cache.hpp for the data layout.
#include "dinero/engine_cache.hpp"

#include <bit>
#include <cassert>
#include <climits>

namespace nodetrace::cachesim::detail {

namespace {

int log2_exact(std::uint64_t power_of_two) { return std::countr_zero(power_of_two); }

}  // namespace

Cache::Cache(const CacheConfig& config, LibcRandom& random)
    : config_(config),
      lg2_block_(log2_exact(config.block_size)),
      lg2_sub_block_(log2_exact(config.effective_sub_block_size())),
      block_mask_((std::uint64_t{1} << lg2_block_) - 1),
      sub_block_mask_((std::uint64_t{1} << lg2_sub_block_) - 1),
      whole_blocks_(lg2_sub_block_ == lg2_block_),
      random_(random) {
  const std::uint64_t sets = config.size / (std::uint64_t{config.block_size} * config.assoc);
  sets_ = static_cast<std::uint32_t>(sets);
  set_mask_ = sets - 1;
  full_set_ = sets_;
  const std::uint32_t stack_count = sets_ + (config.classify_misses ? 1 : 0);
  stacks_.resize(stack_count);
  std::uint64_t node_count = std::uint64_t{sets_} * (config.assoc + 1);
  if (config.classify_misses) node_count += std::uint64_t{sets_} * config.assoc + 1;
  nodes_.resize(node_count);
  std::uint32_t base = 0;
  for (std::uint32_t s = 0; s < stack_count; ++s) {
    const std::uint32_t n = 1 + config.assoc * (s < sets_ ? 1 : sets_);
    Stack& stack = stacks_[s];
    stack.top = base;
    stack.size = n;
    stack.hashed = n > kHashThreshold;
    for (std::uint32_t j = 0; j < n; ++j) {
      Node& node = nodes_[base + j];
      node.down = base + (j + 1) % n;
      node.up = base + (j + n - 1) % n;
    }
    base += n;
  }
}

std::uint32_t Cache::sub_block_bits(const Ref& m) const {
  // ((d4addr)1 << n) - 1 in 32 bits: x86 shifts by n mod 32, so 32 makes 0.
  const std::uint64_t count = sub_blocks_touched(m);
  const std::uint32_t mask = (std::uint32_t{1} << (count & 31)) - 1;
  const std::uint64_t shift = (m.address - block_of(m.address)) >> lg2_sub_block_;
  return static_cast<std::uint32_t>(shift >= 32 ? 0 : mask << shift);
}

std::uint32_t Cache::touched_bits(const Ref& m) const {
  const std::uint64_t count = sub_blocks_touched(m);
  const std::uint64_t mask = count >= 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << count) - 1;
  const std::uint64_t shift = (m.address - block_of(m.address)) >> lg2_sub_block_;
  return static_cast<std::uint32_t>(shift >= 64 ? 0 : mask << shift);
}

std::uint32_t Cache::find(std::uint32_t stack, std::uint64_t block) const {
  const Stack& s = stacks_[stack];
  if (s.hashed) {
    const auto& index = stack == full_set_ && config_.classify_misses ? shadow_index_ : index_;
    const auto it = index.find(block);
    return it == index.end() ? kNone : it->second;
  }
  // The bottom node is always invalid, so the walk ends.
  std::uint32_t p = s.top;
  while (nodes_[p].block != block && nodes_[p].valid != 0) p = nodes_[p].down;
  return nodes_[p].valid != 0 ? p : kNone;
}

void Cache::move_to_top(std::uint32_t stack, std::uint32_t node) {
  Stack& s = stacks_[stack];
  const std::uint32_t top = s.top;
  if (node == top) return;
  // The stack is a ring: the bottom node is just above the top, so making the
  // bottom node the top needs only the top pointer to move.
  if (nodes_[top].up != node) relink_above_top(top, node);
  s.top = node;
}

void Cache::move_to_bottom(std::uint32_t stack, std::uint32_t node) {
  Stack& s = stacks_[stack];
  const std::uint32_t top = s.top;
  const std::uint32_t bottom = nodes_[top].up;
  if (node == bottom) return;
  if (node == top) {
    s.top = nodes_[top].down;
    return;
  }
  relink_above_top(top, node);
}

void Cache::relink_above_top(std::uint32_t top, std::uint32_t node) {
  const std::uint32_t bottom = nodes_[top].up;
  Node& p = nodes_[node];
  nodes_[p.down].up = p.up;
  nodes_[p.up].down = p.down;
  p.up = bottom;
  p.down = top;
  nodes_[bottom].down = node;
  nodes_[top].up = node;
}

std::uint32_t Cache::nth_from_top(std::uint32_t stack, std::uint32_t n) const {
  const Stack& s = stacks_[stack];
  std::uint32_t p = s.top;
  if (n <= s.size / 2) {
    for (std::uint32_t i = 1; i < n; ++i) p = nodes_[p].down;
  } else {
    for (std::uint32_t i = s.size + 1; i > n; --i) p = nodes_[p].up;
  }
  return p;
}

void Cache::index_node(std::uint32_t stack, std::uint32_t node) {
  if (!stacks_[stack].hashed) return;
  auto& index = stack == full_set_ && config_.classify_misses ? shadow_index_ : index_;
  index[nodes_[node].block] = node;
}

void Cache::unindex_node(std::uint32_t stack, std::uint32_t node) {
  if (!stacks_[stack].hashed) return;
  auto& index = stack == full_set_ && config_.classify_misses ? shadow_index_ : index_;
  index.erase(nodes_[node].block);
}

// The replacement policy's update of a stack: on a hit (`hit` != kNone) LRU
// moves the node to the top; on a miss the spare bottom node takes the block
// and becomes the top. Random then sends a random older node of a full set to
// the bottom, where the caller evicts it.
std::uint32_t Cache::replace(std::uint32_t stack, std::uint64_t block, std::uint32_t hit) {
  Stack& s = stacks_[stack];
  if (hit != kNone) {
    if (config_.replacement == ReplacementPolicy::Lru) move_to_top(stack, hit);
    return hit;
  }
  const std::uint32_t node = nodes_[s.top].up;
  assert(nodes_[node].valid == 0);
  nodes_[node].block = block;
  index_node(stack, node);
  s.top = node;
  if (config_.replacement == ReplacementPolicy::Random && nodes_[nodes_[node].up].valid != 0) {
    const std::uint32_t older = s.size - 1;
    move_to_bottom(stack, nth_from_top(stack, 2 + static_cast<std::uint32_t>(random_.next() % older)));
  }
  return node;
}

void Cache::invalidate_node(std::uint32_t stack, std::uint32_t node) {
  nodes_[node].valid = 0;
  move_to_bottom(stack, node);
  unindex_node(stack, node);
}

// Queues writes of the dirty valid sub-blocks of a block, one per contiguous
// run, lowest address first (so drained highest first).
void Cache::write_back_block(std::uint32_t node) {
  Node& p = nodes_[node];
  std::uint32_t bits = p.valid & p.dirty;
  const std::uint64_t sub_block = std::uint64_t{1} << lg2_sub_block_;
  std::uint64_t address = p.block;
  std::uint32_t bit = 1;
  do {
    Ref w;
    w.type = kWrite;
    for (; (bits & bit) == 0; bit <<= 1) address += sub_block;
    const std::uint64_t start = address;
    w.address = start & kAddressMask;
    for (; bit != 0 && (bits & bit) != 0; bit <<= 1) {
      address += sub_block;
      bits &= ~bit;
    }
    w.size = static_cast<std::uint16_t>(address - start);
    pending_.push_back(w);
  } while (bits != 0);
  p.dirty = 0;
}

// The infinite cache of blocks ever seen, for miss classification.
// Returns 0 when every touched sub-block was seen before, 1 when nothing of
// the block (or, when the reference covers all the block or there is one
// sub-block per block, nothing of what it touches) was seen, else -1.
int Cache::infinite_cache(const Ref& m) {
  const std::uint32_t touched = touched_bits(m);
  const std::uint64_t touched_count = sub_blocks_touched(m);
  const std::uint32_t per_block = 1u << (lg2_block_ - lg2_sub_block_);
  auto [it, inserted] = seen_.try_emplace(block_of(m.address), 0u);
  if (inserted) {
    it->second = touched;
    return 1;
  }
  std::uint32_t& seen = it->second;
  if ((seen & touched) == touched) return 0;
  std::uint32_t counted = seen & touched;
  if (per_block != 1 && touched_count != per_block) counted = seen;
  seen |= touched;
  return counted == 0 ? 1 : -1;
}

// Dinero clears (lg2 block - lg2 sub-block) bits from the start of the block
// when one block is invalidated; reproduced as it is.
void Cache::invalidate_infinite_cache(const Ref& m) {
  if (m.size == 0) {
    seen_.clear();
    return;
  }
  const auto it = seen_.find(block_of(m.address));
  if (it == seen_.end()) return;
  const int count = lg2_block_ - lg2_sub_block_;
  it->second &= ~static_cast<std::uint32_t>((std::uint64_t{1} << count) - 1);
}

void Cache::copy_back(const Ref& m) {
  pending_.push_back(m);  // propagated towards memory after this cache's writes
  if (m.size > 0) {
    const std::uint32_t node = find(set_of(m.address), block_of(m.address));
    if (node != kNone && (nodes_[node].dirty & nodes_[node].valid) != 0) write_back_block(node);
  } else {
    for (std::uint32_t s = 0; s < sets_; ++s) {
      const std::uint32_t top = stacks_[s].top;
      for (std::uint32_t p = top; nodes_[p].down != top; p = nodes_[p].down) {
        if ((nodes_[p].dirty & nodes_[p].valid) != 0) write_back_block(p);
      }
    }
  }
  drain_pending();
}

void Cache::invalidate(const Ref& m) {
  pending_.push_back(m);
  if (m.size > 0) {
    const std::uint64_t block = block_of(m.address);
    const std::uint32_t set = set_of(m.address);
    std::uint32_t node = find(set, block);
    if (node != kNone) invalidate_node(set, node);
    if (config_.classify_misses && (node = find(full_set_, block)) != kNone) {
      invalidate_node(full_set_, node);
    }
  } else {
    for (std::uint32_t s = 0; s < stacks_.size(); ++s) {
      // Valid nodes are the first ones from the top.
      std::uint32_t p = stacks_[s].top;
      for (std::uint32_t i = 0; i < stacks_[s].size && nodes_[p].valid != 0; ++i) {
        nodes_[p].valid = 0;
        p = nodes_[p].down;
      }
    }
    index_.clear();
    shadow_index_.clear();
  }
  if (config_.classify_misses) invalidate_infinite_cache(m);
  drain_pending();
}

void Cache::drain_pending() {
  // A reference made from this loop to this same cache (the rest of a split
  // reference) leaves its own queued references to this loop: the order is
  // the same LIFO order, without recursion as deep as the pieces are many.
  if (draining_) return;
  draining_ = true;
  while (!pending_.empty()) {
    Ref m = pending_.back();
    pending_.pop_back();
    if (m.multi_block_rest || m.prefetch) {
      // Both are references to this same cache; a prefetch stays one.
      m.multi_block_rest = false;
      ref(m);
      continue;
    }
    switch (m.type) {
      case kRead:
      case kInstructionFetch:
      case kMisc:
        stats.bytes_from_memory += m.size;
        break;
      case kWrite:
        stats.bytes_to_memory += m.size;
        break;
      default:  // copy-back and invalidate are not traffic
        break;
    }
    if (downstream != nullptr) downstream->ref(m);
  }
  draining_ = false;
}

void Cache::demand_ref(Ref m) {
  const std::uint64_t block = block_of(m.address);
  // Fast path: a read, instruction fetch or misc reference within one block
  // that hits the most recent block of its set changes nothing but a count.
  if (m.type != kWrite && !config_.classify_misses && config_.fetch == FetchPolicy::Demand &&
      m.size != 0 &&
      block == block_of(m.address + m.size - 1)) {
    const Node& top = nodes_[stacks_[set_of(m.address)].top];
    if (top.block == block && top.valid != 0) {
      const std::uint32_t bits = whole_blocks_ ? 1u : sub_block_bits(m);
      if ((top.valid & bits) == bits) {
        ++stats.fetches[m.type];
        return;
      }
    }
  }
  // A reference crossing a block boundary: simulate the part in this block
  // now and queue the rest, as a new reference to this same cache.
  if (block != block_of(m.address + m.size - 1)) {
    Ref rest;
    rest.address = block_of(block + (block_mask_ + 1));
    rest.type = m.type;
    rest.multi_block_rest = true;
    const auto first_size = static_cast<std::uint16_t>((block_mask_ + 1) - (m.address & block_mask_));
    rest.size = static_cast<std::uint16_t>(m.size - first_size);
    pending_.push_back(rest);
    ++stats.multi_block_refs;
    m.size = first_size;
  }
  const std::uint8_t type = m.type;
  const bool is_write = type == kWrite;
  FetchCounts& counts = m.prefetch ? static_cast<FetchCounts&>(stats.prefetch) : stats;
  const std::uint32_t set = set_of(m.address);
  const std::uint32_t sub_bits = sub_block_bits(m);
  const std::uint64_t touched_bytes = sub_blocks_touched(m) << lg2_sub_block_;
  const bool covers_sub_blocks = m.size == touched_bytes;

  bool allocate = false;
  if (is_write) {
    switch (config_.write_allocate) {
      case WriteAllocate::Always: allocate = true; break;
      case WriteAllocate::Never: allocate = false; break;
      case WriteAllocate::NoFetch: allocate = covers_sub_blocks; break;
    }
  }

  std::uint32_t node = stacks_[set].top;
  if (!(nodes_[node].block == block && nodes_[node].valid != 0)) node = find(set, block);
  const bool block_miss = node == kNone;
  const bool miss = block_miss || (sub_bits & nodes_[node].valid) != sub_bits;

  // Only demand reads and instruction fetches prefetch (not misc references).
  if (config_.fetch != FetchPolicy::Demand && !m.prefetch && (type == kRead || type == kInstructionFetch)) {
    prefetch_for(m, miss, node);
  }

  bool write_back = false;
  if (!is_write || !block_miss || allocate) {
    node = replace(set, block, block_miss ? kNone : node);
    Node& p = nodes_[node];
    if (block_miss) {
      p.dirty = 0;
      p.referenced = 0;
    }
    p.valid |= sub_bits;
    if (!m.prefetch) p.referenced |= sub_bits;
    if (is_write) {
      switch (config_.write_back) {
        case WriteBack::Always: write_back = true; break;
        case WriteBack::Never: write_back = false; break;
        // Tested after the sub-blocks were marked valid, as Dinero does.
        case WriteBack::NoFetch: write_back = (sub_bits & ~p.valid) == 0 || covers_sub_blocks; break;
      }
    }
    if (write_back) p.dirty |= sub_bits;
    if (block_miss) {
      const std::uint32_t victim = nodes_[stacks_[set].top].up;
      if (nodes_[victim].valid != 0) {
        if ((nodes_[victim].valid & nodes_[victim].dirty) != 0) write_back_block(victim);
        unindex_node(set, victim);
        nodes_[victim].valid = 0;
      }
    }
  }

  if (is_write && !write_back) pending_.push_back(m);  // write through
  if (miss && (!is_write || (allocate && !covers_sub_blocks))) {
    Ref fetch;
    fetch.type = is_write ? std::uint8_t{kRead} : type;
    fetch.address = sub_block_of(m.address);
    fetch.size = static_cast<std::uint16_t>(touched_bytes);
    pending_.push_back(fetch);
  }

  if (config_.classify_misses) {
    std::uint32_t full = stacks_[full_set_].top;
    if (nodes_[full].block != block) {
      full = find(full_set_, block);
    } else if (nodes_[full].valid == 0) {
      full = kNone;
    }
    const bool full_block_miss = full == kNone;
    const bool full_miss = full_block_miss || (sub_bits & nodes_[full].valid) != sub_bits;
    if (!is_write || !full_block_miss || allocate) {
      full = replace(full_set_, block, full);
      nodes_[full].valid |= sub_bits;
    }
    if (miss) {
      int infinite_miss = 0;
      if (!full_miss) {
        ++counts.conflict[type];
      } else {
        infinite_miss = infinite_cache(m);
        if (infinite_miss != 0) {
          ++counts.compulsory[type];
        } else {
          ++counts.capacity[type];
        }
      }
      if (block_miss) {
        if (!full_block_miss) {
          ++counts.conflict_block[type];
        } else if (infinite_miss == 1) {
          ++counts.compulsory_block[type];
        } else {
          ++counts.capacity_block[type];
        }
      }
    }
    if (full_block_miss) {
      const std::uint32_t victim = nodes_[stacks_[full_set_].top].up;
      if (nodes_[victim].valid != 0) {
        unindex_node(full_set_, victim);
        nodes_[victim].valid = 0;
      }
    }
  }

  ++counts.fetches[type];
  if (miss) {
    ++counts.misses[type];
    if (block_miss) ++counts.block_misses[type];
  }
  if (!pending_.empty()) drain_pending();
}

void Cache::prefetch_for(const Ref& m, bool miss, std::uint32_t node) {
  switch (config_.fetch) {
    case FetchPolicy::Miss:
      if (!miss) return;
      break;
    case FetchPolicy::Tagged:
      // Also on the first demand reference to a sub-block a prefetch brought.
      if (!miss && (sub_block_bits(m) & nodes_[node].referenced) != 0) return;
      break;
    default:
      break;
  }
  // Dinero IV keeps the distance in bytes in an int: the same wrap-around.
  const auto distance = static_cast<std::int32_t>(config_.prefetch_distance << lg2_sub_block_);
  const std::uint64_t target = m.address + static_cast<std::uint64_t>(std::int64_t{distance});
  if (config_.fetch == FetchPolicy::LoadForward && block_of(target) != block_of(m.address)) return;
  Ref pf;
  pf.address = sub_block_of(target);
  pf.size = static_cast<std::uint16_t>(sub_block_mask_ + 1);
  pf.type = m.type;
  pf.prefetch = true;
  if (config_.fetch == FetchPolicy::SubBlock && block_of(pf.address) != block_of(m.address)) {
    pf.address = (pf.address - (block_mask_ + 1)) & kAddressMask;  // wrap round within the block
  }
  // Dinero IV's test: random() / (INT_MAX / 100) < percentage.
  if (config_.prefetch_abort > 0 && random_.next() / (INT_MAX / 100) < config_.prefetch_abort) return;
  pending_.push_back(pf);
}

}  // namespace nodetrace::cachesim::detail
