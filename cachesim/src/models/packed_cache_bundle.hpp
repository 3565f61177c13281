// Internal: packed caches (packed_policy_cache.hpp) run together over one
// list of references: each reference goes through every cache of the
// bundle before the next one is read. Their misses mostly coincide (on a
// rendered kd-tree trace, of the references a policy grid's filter keeps
// for 128 sets, 73 % hit in all six caches of plru, srrip and drrip at 4
// and 8 ways, and 15 % miss in all six), so the branch predictor, seeing
// the caches' hit-or-miss branches one after another, learns the later
// ones from the first. The references are read once for all.
// Each cache counts exactly as it would alone: none reads another's state.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <span>
#include <tuple>
#include <utility>
#include <vector>

#include "models/packed_policy_cache.hpp"

namespace nodetrace::cachesim {

class PackedCacheBundle {
 public:
  // Adds a cache of 2, 4, 8 or 16 ways under plru or an rrip policy;
  // returns its index for misses().
  std::size_t add(const CacheGeometry& geometry) {
    switch (geometry.assoc) {
      case 2: return add_to(std::get<0>(groups_), geometry);
      case 4: return add_to(std::get<1>(groups_), geometry);
      case 8: return add_to(std::get<2>(groups_), geometry);
      default: return add_to(std::get<3>(groups_), geometry);
    }
  }

  std::uint64_t misses(std::size_t index) const {
    const Member member = members_[index];
    std::uint64_t misses = 0;
    for_each_group([&](const auto& group) {
      if (member.ways != group.kWays) return;
      misses = member.plru ? group.plru[member.slot].misses() : group.rrip[member.slot].misses();
    });
    return misses;
  }

  // Runs `count` references through every cache (`invalidates`: some are
  // invalidations; `beyond_narrow`: a block needs a 64-bit tag).
  void run(const std::uint64_t* blocks, const PackedReference* kinds, std::size_t count, bool invalidates,
           bool beyond_narrow) {
    if (beyond_narrow && !wide_) {
      for_each_cache([](auto& cache) { cache.widen(); });
      wide_ = true;
    }
    if (wide_) {
      run_with<std::uint64_t>(blocks, kinds, count, invalidates);
    } else {
      run_with<std::uint32_t>(blocks, kinds, count, invalidates);
    }
  }

 private:
  template <unsigned kGroupWays>
  struct Group {
    static constexpr unsigned kWays = kGroupWays;
    std::vector<PackedPolicyCache<PackedPlru<kWays>, kWays>> plru;
    std::vector<PackedPolicyCache<PackedRrip<kWays>, kWays>> rrip;
  };
  struct Member {
    unsigned ways;
    bool plru;
    std::size_t slot;
  };

  template <typename GroupOf>
  std::size_t add_to(GroupOf& group, const CacheGeometry& geometry) {
    const bool plru = geometry.replacement == ReplacementPolicy::Plru;
    const std::size_t slot = plru ? group.plru.size() : group.rrip.size();
    if (plru) {
      group.plru.emplace_back(geometry);
    } else {
      group.rrip.emplace_back(geometry);
    }
    members_.push_back(Member{GroupOf::kWays, plru, slot});
    return members_.size() - 1;
  }

  template <typename Visit>
  void for_each_group(Visit visit) const {
    std::apply([&](const auto&... group) { (visit(group), ...); }, groups_);
  }
  template <typename Visit>
  void for_each_cache(Visit visit) {
    std::apply(
        [&](auto&... group) {
          ((std::for_each(group.plru.begin(), group.plru.end(), visit),
            std::for_each(group.rrip.begin(), group.rrip.end(), visit)),
           ...);
        },
        groups_);
  }

  template <typename Tag>
  void run_with(const std::uint64_t* blocks, const PackedReference* kinds, std::size_t count, bool invalidates) {
    if (invalidates) {
      // Rare (only traces with invalidations): a cache at a time.
      for_each_cache([&](auto& cache) { cache.template run<Tag>(blocks, kinds, count); });
      return;
    }
    // The groups' caches as spans held in locals: read through the
    // vectors, their bounds would be loaded again for every reference
    // (the caches' byte-sized words may alias anything).
    const auto spans = std::apply(
        [](auto&... group) { return std::make_tuple(std::span(group.plru)..., std::span(group.rrip)...); }, groups_);
    for (std::size_t r = 0; r < count; ++r) {
      const std::uint64_t block = blocks[r];
      const bool refetched = kinds[r] == PackedReference::Refetched;
      std::apply(
          [&](const auto&... caches) {
            ((std::for_each(caches.begin(), caches.end(),
                            [&](auto& cache) { cache.template access<Tag>(block, refetched); })),
             ...);
          },
          spans);
    }
  }

  std::tuple<Group<2>, Group<4>, Group<8>, Group<16>> groups_;
  std::vector<Member> members_;  // by index
  bool wide_ = false;
};

}  // namespace nodetrace::cachesim
