// The cache models a configuration's simulator is composed of (see
// config_simulator.cpp): a direct-mapped table, a set-associative cache, a
// cache of a policy object (policy_cache.hpp), MIN (opt_cache.hpp), any of
// those behind one interface (AnyCache), the retain set of the split
// scheme's high cache, and no cache (the high side of `single`). Each takes
// block numbers; the table and the retain set expose their slots so the fast
// loops can pick one without a branch. MIN counts its misses at the end:
// deferred_misses() (0 for the others) is added to what access() returned.
#pragma once

#include <algorithm>
#include <bit>
#include <cstdint>
#include <memory>
#include <type_traits>
#include <vector>

#include "nodetrace/cachesim/models/set_associative_cache.hpp"
#include "models/marked_recency_sets.hpp"
#include "models/opt_cache.hpp"
#include "models/policy_cache.hpp"
#include "models/replacement_policies.hpp"
#include "models/retained_blocks.hpp"
#include "models/treelet_prefetcher.hpp"

namespace nodetrace::cachesim {

// A direct-mapped cache: one block per set, so no policy.
class DirectMappedTable {
 public:
  explicit DirectMappedTable(std::uint64_t sets) : slots_(sets, SetAssociativeCache::kInvalid), mask_(sets - 1) {}
  bool access(std::uint64_t block) {
    std::uint64_t& slot = slots_[block & mask_];
    const bool miss = slot != block;
    slot = block;
    return miss;
  }
  void invalidate(std::uint64_t block) {
    if (std::uint64_t& slot = slots_[block & mask_]; slot == block) slot = SetAssociativeCache::kInvalid;
  }
  void clear() { std::fill(slots_.begin(), slots_.end(), SetAssociativeCache::kInvalid); }
  std::uint64_t* slots() { return slots_.data(); }
  std::uint64_t mask() const { return mask_; }

 private:
  std::vector<std::uint64_t> slots_;
  std::uint64_t mask_;
};

// The `retain` high cache: the distinct blocks touched in the current
// animation frame, loaded once each. A direct-mapped filter of blocks
// already loaded answers most fetches with one compare.
class RetainSet {
 public:
  explicit RetainSet(std::uint64_t capacity_blocks)
      : filter_(std::bit_ceil(std::max<std::uint64_t>(64, 4 * capacity_blocks))),
        blocks_(capacity_blocks) {}
  // True when `block` is a new load this frame (then count() may exceed
  // capacity(): the caller's error).
  bool access(std::uint64_t block) {
    std::uint64_t& slot = filter_.slots()[block & filter_.mask()];
    if (slot == block) return false;
    slot = block;
    return blocks_.insert(block);
  }
  // For the fast loops: the filter missed (`block` is in its slot now).
  [[gnu::noinline]] bool insert_after_filter(std::uint64_t block) { return blocks_.insert(block); }
  void begin_animation_frame() {
    blocks_.clear();
    filter_.clear();
  }
  std::uint64_t count() const { return blocks_.count(); }
  std::uint64_t capacity() const { return blocks_.capacity(); }
  DirectMappedTable& filter() { return filter_; }

 private:
  DirectMappedTable filter_;
  RetainedBlocks blocks_;
};

// A cache model of any type behind a virtual call: for the caches a fast
// loop does not need (the high cache under `cache`).
class AnyCache {
 public:
  template <typename Model>
  explicit AnyCache(Model model) : model_(std::make_unique<Holder<Model>>(std::move(model))) {}
  bool access(std::uint64_t block) { return model_->access(block); }
  void invalidate(std::uint64_t block) { model_->invalidate(block); }
  std::uint64_t deferred_misses() const { return model_->deferred_misses(); }
  void begin_treelets(const formats::TreeletMap* map) { model_->begin_treelets(map); }
  PrefetchCounts prefetch_counts() const { return model_->prefetch_counts(); }

 private:
  struct Interface {
    virtual ~Interface() = default;
    virtual bool access(std::uint64_t block) = 0;
    virtual void invalidate(std::uint64_t block) = 0;
    virtual std::uint64_t deferred_misses() const = 0;
    virtual void begin_treelets(const formats::TreeletMap* map) = 0;
    virtual PrefetchCounts prefetch_counts() const = 0;
  };
  template <typename Model>
  struct Holder final : Interface {
    explicit Holder(Model held) : model(std::move(held)) {}
    bool access(std::uint64_t block) override { return model.access(block); }
    void invalidate(std::uint64_t block) override { model.invalidate(block); }
    std::uint64_t deferred_misses() const override {
      if constexpr (std::is_same_v<Model, OptCache>) {
        return model.misses();
      } else {
        return 0;
      }
    }
    void begin_treelets(const formats::TreeletMap* map) override {
      if constexpr (requires { model.begin_treelets(map); }) model.begin_treelets(map);
    }
    PrefetchCounts prefetch_counts() const override {
      if constexpr (requires { model.prefetch_counts(); }) {
        return model.prefetch_counts();
      } else {
        return {};
      }
    }
    Model model;
  };
  std::unique_ptr<Interface> model_;
};

// Where an opt cache's stream comes from: shared with the opt caches of
// the same fetches (the first of them records it), or its own when null.
struct OptSource {
  std::shared_ptr<SharedOptStream> shared;
  bool records = true;
};

// Calls `use` with the model of a demand-fetch cache of `geometry`: a table
// when direct mapped (every policy but opt misses as LRU then), a policy
// cache for the policies Dinero IV does not have and for sets of many ways,
// MIN for opt (its stream from `opt`), else the shifting-array cache.
template <typename Use>
auto with_cache_model(const CacheGeometry& geometry, const OptSource& opt, Use&& use) {
  validate_geometry(geometry, "cache");
  switch (geometry.replacement) {
    case ReplacementPolicy::Opt: return use(OptCache(geometry, opt.shared, opt.records));
    case ReplacementPolicy::Plru:
    case ReplacementPolicy::Srrip:
    case ReplacementPolicy::Brrip:
    case ReplacementPolicy::Drrip:
      if (geometry.assoc == 1) break;
      if (geometry.replacement == ReplacementPolicy::Plru) return use(PolicyCache<TreePlru>(geometry));
      return use(PolicyCache<Rrip>(geometry));
    case ReplacementPolicy::Lru:
    case ReplacementPolicy::Fifo:
      if (geometry.assoc > kScanWays) return use(PolicyCache<RecencyOrder>(geometry));
      break;
    case ReplacementPolicy::Random:
      if (geometry.assoc > kScanWays) return use(PolicyCache<DrawnOrder>(geometry));
      break;
  }
  if (geometry.assoc == 1) return use(DirectMappedTable(geometry.size / geometry.block_size));
  return use(SetAssociativeCache(geometry));
}

// The high side of `single`: never reached.
struct NoCache {
  bool access(std::uint64_t) { return false; }
  void invalidate(std::uint64_t) {}
};

template <typename Model>
std::uint64_t deferred_misses(const Model& model) {
  if constexpr (std::is_same_v<Model, OptCache>) {
    return model.misses();
  } else if constexpr (std::is_same_v<Model, AnyCache>) {
    return model.deferred_misses();
  } else {
    return 0;
  }
}

// A treelet prefetcher's counts (none for the other models).
template <typename Model>
PrefetchCounts prefetch_counts(const Model& model) {
  if constexpr (requires { model.prefetch_counts(); }) {
    return model.prefetch_counts();
  } else {
    return {};
  }
}

// Gives a treelet prefetcher its animation frame's map (the other models have none).
template <typename Model>
void begin_treelets(Model& model, const formats::TreeletMap* map) {
  if constexpr (requires { model.begin_treelets(map); }) model.begin_treelets(map);
}

// Calls `use` with a treelet prefetcher of `geometry` (any policy but opt,
// which callers refuse before).
template <typename Use>
auto with_treelet_prefetcher(const CacheGeometry& geometry, std::uint64_t limit_bytes, Use&& use) {
  validate_geometry(geometry, "cache");
  // One way: every policy replaces the set's block (random's draws choose among one).
  if (geometry.assoc == 1) return use(TreeletPrefetcher<SlotMarkedCache<DirectMappedSlots>>(geometry, limit_bytes));
  switch (geometry.replacement) {
    case ReplacementPolicy::Random:
      return use(TreeletPrefetcher<SlotMarkedCache<PolicyCache<DrawnOrder>>>(geometry, limit_bytes));
    case ReplacementPolicy::Plru:
      return use(TreeletPrefetcher<SlotMarkedCache<PolicyCache<TreePlru>>>(geometry, limit_bytes));
    case ReplacementPolicy::Srrip:
    case ReplacementPolicy::Brrip:
    case ReplacementPolicy::Drrip:
      return use(TreeletPrefetcher<SlotMarkedCache<PolicyCache<Rrip>>>(geometry, limit_bytes));
    default:
      // LRU and FIFO: shifting arrays while a set is scanned way by way.
      if (geometry.assoc == 2) return use(TreeletPrefetcher<MarkedRecencySets<2>>(geometry, limit_bytes));
      if (geometry.assoc == 4) return use(TreeletPrefetcher<MarkedRecencySets<4>>(geometry, limit_bytes));
      if (geometry.assoc == 8) return use(TreeletPrefetcher<MarkedRecencySets<8>>(geometry, limit_bytes));
      if (geometry.assoc <= kScanWays) return use(TreeletPrefetcher<MarkedRecencySets<>>(geometry, limit_bytes));
      return use(TreeletPrefetcher<SlotMarkedCache<PolicyCache<RecencyOrder>>>(geometry, limit_bytes));
  }
}

}  // namespace nodetrace::cachesim
