// Internal: the replacement policies of PolicyCache (policy_cache.hpp). Each
// is told of hits, asked for a victim of a full set (which it forgets), told
// of fills and invalidations; way numbers are within the set. The rules are
// docs/guide/replacement-policies.md's, stated again where they are kept.
#pragma once

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstring>
#include <vector>

#include "dinero/libc_random.hpp"
#include "nodetrace/cachesim/models/cache_geometry.hpp"

namespace nodetrace::cachesim {

// LRU and FIFO as orders of the valid ways, most recent first (LRU: used,
// FIFO: filled), a circular doubly linked list per set: O(1) a reference.
class RecencyOrder {
 public:
  RecencyOrder(std::uint64_t sets, const CacheGeometry& geometry)
      : assoc_(geometry.assoc),
        policy_(geometry.replacement),
        next_(sets * geometry.assoc),
        previous_(sets * geometry.assoc),
        head_(sets, kNone) {}

  void hit(std::uint64_t set, std::uint32_t way) {
    if (policy_ != ReplacementPolicy::Lru) return;
    const std::uint32_t slot = slot_of(set, way);
    if (head_[set] == slot) return;
    unlink(set, slot);
    push_front(set, slot);
  }
  std::uint32_t victim(std::uint64_t set) {
    const std::uint32_t slot = previous_[head_[set]];  // the least recent
    unlink(set, slot);
    return static_cast<std::uint32_t>(slot - set * assoc_);
  }
  void fill(std::uint64_t set, std::uint32_t way) { push_front(set, slot_of(set, way)); }
  void invalidate(std::uint64_t set, std::uint32_t way) { unlink(set, slot_of(set, way)); }

 private:
  static constexpr std::uint32_t kNone = ~std::uint32_t{0};

  std::uint32_t slot_of(std::uint64_t set, std::uint32_t way) const {
    return static_cast<std::uint32_t>(set * assoc_ + way);
  }
  void unlink(std::uint64_t set, std::uint32_t slot) {
    if (next_[slot] == slot) {
      head_[set] = kNone;
      return;
    }
    next_[previous_[slot]] = next_[slot];
    previous_[next_[slot]] = previous_[slot];
    if (head_[set] == slot) head_[set] = next_[slot];
  }
  void push_front(std::uint64_t set, std::uint32_t slot) {
    const std::uint32_t head = head_[set];
    if (head == kNone) {
      next_[slot] = previous_[slot] = slot;
    } else {
      next_[slot] = head;
      previous_[slot] = previous_[head];
      next_[previous_[head]] = slot;
      previous_[head] = slot;
    }
    head_[set] = slot;
  }

  std::uint32_t assoc_;
  ReplacementPolicy policy_;
  std::vector<std::uint32_t> next_;      // per slot: the next less recent way of its set
  std::vector<std::uint32_t> previous_;  // per slot: the next more recent
  std::vector<std::uint32_t> head_;      // per set: the most recent slot, kNone when empty
};

// Dinero IV's random replacement: the valid ways in fill order, most recent
// first, and a full set evicts the k-th (from 0) of that order with k =
// random() % ways, glibc's random() after srandom(1) (engine_cache.cpp
// draws the same). The order is an array per set: finding the k-th is an
// index, removing it moves the k more recent ways by one.
class DrawnOrder {
 public:
  DrawnOrder(std::uint64_t sets, const CacheGeometry& geometry)
      : assoc_(geometry.assoc), order_(sets * geometry.assoc), count_(sets, 0), front_free_(sets, 0) {}

  void hit(std::uint64_t, std::uint32_t) {}
  std::uint32_t victim(std::uint64_t set) {
    std::uint32_t* const order = order_.data() + set * assoc_;
    const std::uint32_t k = random_.next() % assoc_;
    const std::uint32_t way = order[k];
    std::move_backward(order, order + k, order + k + 1);  // order[0] is free for the fill
    front_free_[set] = 1;
    --count_[set];
    return way;
  }
  void fill(std::uint64_t set, std::uint32_t way) {
    std::uint32_t* const order = order_.data() + set * assoc_;
    if (front_free_[set] == 0) std::move_backward(order, order + count_[set], order + count_[set] + 1);
    front_free_[set] = 0;
    order[0] = way;
    ++count_[set];
  }
  void invalidate(std::uint64_t set, std::uint32_t way) {
    std::uint32_t* const order = order_.data() + set * assoc_;
    std::uint32_t* const end = order + count_[set];
    std::uint32_t* const at = std::find(order, end, way);
    std::move(at + 1, end, at);
    --count_[set];
  }

 private:
  std::uint32_t assoc_;
  std::vector<std::uint32_t> order_;       // per set: its valid ways, most recently filled first
  std::vector<std::uint32_t> count_;       // per set: valid ways
  std::vector<std::uint8_t> front_free_;   // per set: victim() left order[0] for fill()
  detail::LibcRandom random_;
};

// Tree pseudo-LRU: a binary tree of ways - 1 bits per set (node 1 the root,
// node n's children 2n and 2n + 1, leaves ways + way). Each bit points to
// the half to evict from; a hit or a fill points every bit on the way's path
// away from it. Equals LRU at 1 and 2 ways.
class TreePlru {
 public:
  TreePlru(std::uint64_t sets, const CacheGeometry& geometry)
      : assoc_(geometry.assoc),
        levels_(std::countr_zero(geometry.assoc)),
        bits_(sets * geometry.assoc, 0) {}

  void hit(std::uint64_t set, std::uint32_t way) { point_away(set, way); }
  std::uint32_t victim(std::uint64_t set) const {
    const std::uint8_t* const bits = bits_.data() + set * assoc_;
    std::uint32_t node = 1;
    while (node < assoc_) node = 2 * node + bits[node];
    return node - assoc_;
  }
  void fill(std::uint64_t set, std::uint32_t way) { point_away(set, way); }
  void invalidate(std::uint64_t, std::uint32_t) {}

 private:
  void point_away(std::uint64_t set, std::uint32_t way) {
    std::uint8_t* const bits = bits_.data() + set * assoc_;
    std::uint32_t node = 1;
    for (int level = levels_ - 1; level >= 0; --level) {
      const std::uint32_t side = (way >> level) & 1u;
      bits[node] = static_cast<std::uint8_t>(side ^ 1u);
      node = 2 * node + side;
    }
  }

  std::uint32_t assoc_;
  int levels_;
  std::vector<std::uint8_t> bits_;  // per set, assoc entries (entry 0 unused)
};

// The insertion value of an RRIP fill (Jaleel et al., ISCA 2010), one per
// cache: srrip at 2; brrip at 3, except every 32nd brrip insertion of the
// cache (the 32nd, 64th, ... counted from its first) at 2; drrip: set
// dueling with a 10-bit selector PSEL starting at 511. With S sets, L =
// min(32, S / 2) leaders of each kind: in each of the L runs of S / L
// consecutive sets, the first is an srrip leader and the last a brrip
// leader. A miss in an srrip leader adds 1 to PSEL, in a brrip leader takes
// 1 (saturating at 0 and 1023); the other sets insert as brrip while PSEL >=
// 512, else as srrip (a cache of one set has no leaders: srrip).
class RripInsertion {
 public:
  RripInsertion(std::uint64_t sets, ReplacementPolicy policy) : policy_(policy) {
    const std::uint64_t leaders = std::min<std::uint64_t>(32, sets / 2);
    run_ = leaders == 0 ? 0 : sets / leaders;  // a power of two, as `sets`
  }

  // The value of a block filled into `set` now (a miss there). drrip's
  // rule has no branch on the set: whether a set leads and which kind it
  // is follow no pattern a predictor learns, and with few sets every set
  // leads (a policy grid on BART Kitchen: 3.11 s -> 3.04 s of CPU).
  std::uint8_t operator()(std::uint64_t set) {
    if (policy_ == ReplacementPolicy::Srrip) return 2;
    if (policy_ == ReplacementPolicy::Brrip) return bimodal(true);
    const std::uint64_t in_run = set & (run_ - 1);
    const bool leads = run_ != 0;
    const bool srrip_leader = leads & (in_run == 0);
    const bool brrip_leader = leads & (in_run == run_ - 1);
    const bool brrip = brrip_leader | (!srrip_leader & (selector_ >= 512));
    selector_ += static_cast<std::uint32_t>(srrip_leader & (selector_ < kSelectorMax));
    selector_ -= static_cast<std::uint32_t>(brrip_leader & (selector_ > 0));
    return bimodal(brrip);
  }

 private:
  static constexpr std::uint32_t kSelectorMax = 1023;

  // 2, or under `brrip` 3 but 2 for every 32nd such insertion.
  std::uint8_t bimodal(bool brrip) {
    bimodal_insertions_ += brrip;
    return static_cast<std::uint8_t>(2 + (brrip & (bimodal_insertions_ % 32 != 0)));
  }

  ReplacementPolicy policy_;
  std::uint64_t run_ = 0;             // drrip: sets per run holding one leader of each kind
  std::uint32_t selector_ = 511;      // drrip: PSEL
  std::uint64_t bimodal_insertions_ = 0;
};

// Re-reference interval prediction, 2-bit values per way: 0 on a hit; the
// victim is the lowest-numbered way at 3, after ageing every way of the set
// by 3 - (its highest value) when none is; a fill takes RripInsertion's value.
class Rrip {
 public:
  Rrip(std::uint64_t sets, const CacheGeometry& geometry)
      : assoc_(geometry.assoc), values_(sets * geometry.assoc, kDistant), insertion_(sets, geometry.replacement) {}

  void hit(std::uint64_t set, std::uint32_t way) { values_[set * assoc_ + way] = 0; }
  std::uint32_t victim(std::uint64_t set) {
    std::uint8_t* const values = values_.data() + set * assoc_;
    const std::uint8_t highest = *std::max_element(values, values + assoc_);
    if (highest != kDistant) {
      const auto age = static_cast<std::uint8_t>(kDistant - highest);
      for (std::uint32_t way = 0; way < assoc_; ++way) values[way] = static_cast<std::uint8_t>(values[way] + age);
    }
    return static_cast<std::uint32_t>(static_cast<const std::uint8_t*>(std::memchr(values, kDistant, assoc_)) -
                                      values);
  }
  void fill(std::uint64_t set, std::uint32_t way) { values_[set * assoc_ + way] = insertion_(set); }
  void invalidate(std::uint64_t, std::uint32_t) {}

 private:
  static constexpr std::uint8_t kDistant = 3;

  std::uint32_t assoc_;
  std::vector<std::uint8_t> values_;  // per slot
  RripInsertion insertion_;
};

}  // namespace nodetrace::cachesim
