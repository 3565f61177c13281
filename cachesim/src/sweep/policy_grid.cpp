// The policy grid: a chunk's records read once (the first set count's
// filter reads them itself when each is one demand fetch; other records
// are collected into references first), then, for each set count of its
// members (fewest sets first), filtered by that set count's filter and run
// through those members' packed caches together.
#include "sweep/policy_grid.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <map>

#include "models/packed_cache_bundle.hpp"
#include "models/record_blocks.hpp"

namespace nodetrace::cachesim {

using formats::AccessType;
using formats::Record;

namespace {

// References in trace order.
struct References {
  std::vector<std::uint64_t> blocks;
  std::vector<PackedReference> kinds;
  std::size_t count = 0;
  bool invalidates = false;  // some are invalidations

  void make_room(std::size_t most) {
    if (blocks.size() < most) {
      blocks.resize(most);
      kinds.resize(most);
    }
    count = 0;
    invalidates = false;
  }
};

// The caches' geometry, checked.
CacheGeometry grid_geometry(const Configuration& config) {
  const CacheGeometry geometry{config.size, config.block, config.assoc, config.policy};
  validate_geometry(geometry, "cache");
  return geometry;
}

// The filter of one set count: per set, the block its last fetch fetched
// and where that fetch is in the references kept. A fetch of the same block
// again, with no invalidation of it between, is a hit in every cache of
// this set count whose update is idempotent (packed_policy_cache.hpp): it is
// left out, and the kept fetch becomes Refetched. Left out here, a fetch
// would be left out by every larger set count too (each of their sets is
// part of one set here), so each set count filters what the one before it
// kept. Only fetches of the same chunk are joined (the kept one must not
// have been run yet): every chunk starts with no set's block known.
class SetFilter {
 public:
  explicit SetFilter(unsigned log2_sets) : slots_(std::size_t{1} << log2_sets), mask_(slots_.size() - 1) {}

  // Filters `in` into `out`.
  void filter(const References& in, References& out) {
    out.make_room(in.count);
    out.invalidates = in.invalidates;
    const auto block_at = [&](std::size_t r) { return in.blocks[r]; };
    const auto kind_at = [&](std::size_t r) { return in.kinds[r]; };
    if (in.invalidates) {
      out.count = filter_with<true>(in.count, block_at, kind_at, out);
    } else {
      out.count = filter_with<false>(in.count, block_at, kind_at, out);
    }
  }
  // Filters `count` records, each one demand fetch of the block its
  // address shifted right by `shift` gives, into `out`.
  void filter_fetches(const Record* records, std::size_t count, unsigned shift, References& out) {
    out.make_room(count);
    const auto block_at = [=](std::size_t r) { return records[r].address >> shift; };
    const auto kind_at = [](std::size_t) { return PackedReference::Fetch; };
    out.count = filter_with<false>(count, block_at, kind_at, out);
  }

 private:
  // No block: the packed caches' mark of a free way too (and every model's:
  // the block number 2^64 - 1, only 1-byte blocks at the last address, is
  // not simulated apart from it).
  static constexpr std::uint64_t kNoBlock = ~std::uint64_t{0};
  struct Slot {
    std::uint64_t block = kNoBlock;
    std::uint64_t at = 0;  // of the kept fetch of `block`, in this chunk's references
  };

  // Without a branch on the filter's answer: a fetch left out rewrites the
  // kept one as Refetched, another starts a new one.
  template <bool kInvalidates, typename BlockAt, typename KindAt>
  std::size_t filter_with(std::size_t count, BlockAt block_at, KindAt kind_at, References& out) {
    std::fill(slots_.begin(), slots_.end(), Slot{});
    Slot* const slots = slots_.data();
    const std::uint64_t mask = mask_;
    std::uint64_t* const blocks = out.blocks.data();
    PackedReference* const kinds = out.kinds.data();
    std::size_t kept = 0;
    for (std::size_t r = 0; r < count; ++r) {
      const std::uint64_t block = block_at(r);
      const PackedReference kind = kind_at(r);
      Slot& slot = slots[block & mask];
      if constexpr (kInvalidates) {
        if (kind == PackedReference::Invalidate) {
          if (slot.block == block) slot.block = kNoBlock;
          blocks[kept] = block;
          kinds[kept] = kind;
          ++kept;
          continue;
        }
      }
      // All ones when left out; an empty asm keeps the compiler from
      // branching on it.
      std::uint64_t again = std::uint64_t{0} - static_cast<std::uint64_t>(slot.block == block);
      asm("" : "+r"(again));
      const std::size_t at = kept ^ ((kept ^ slot.at) & again);
      blocks[at] = block;
      kinds[at] = static_cast<PackedReference>(static_cast<std::uint8_t>(kind) | (again & 1));  // Fetch becomes Refetched
      slot.block = block;
      slot.at = at;
      kept += 1 - (again & 1);
    }
    return kept;
  }

  std::vector<Slot> slots_;
  std::uint64_t mask_;
};

class PolicyGrid {
 public:
  PolicyGrid(const std::vector<Configuration>& configs, const TraceContext& context)
      : context_(context),
        configs_(configs),
        shift_(static_cast<unsigned>(std::countr_zero(configs.front().block))),
        aligned_din_(context.form == formats::RecordForm::Din && configs.front().block >= 4) {
    std::map<unsigned, std::vector<std::size_t>> by_sets;
    for (std::size_t m = 0; m < configs.size(); ++m) {
      const Configuration& config = configs[m];
      by_sets[static_cast<unsigned>(std::countr_zero(config.size / config.block / config.assoc))].push_back(m);
    }
    where_.resize(configs.size());
    for (auto& [log2_sets, members] : by_sets) {
      Level& level = levels_.emplace_back(Level{SetFilter(log2_sets), {}, {}});
      for (const std::size_t m : members) where_[m] = {levels_.size() - 1, level.caches.add(grid_geometry(configs[m]))};
      filtered_->lists.push_back(SetStacks::Filtered{log2_sets, nullptr, 0});
    }
  }

  std::shared_ptr<const GridFilterOutput> filtered() const { return filtered_; }

  void feed(const Record* records, std::size_t count, const PreparedBatch& prepared) {
    // Every record one demand fetch of one block (din addresses need no
    // rounding: blocks are at least 4 bytes): the first set count filters
    // the records themselves.
    const bool fetches_only = prepared.demand_only && prepared.span_bits < configs_.front().block;
    filtered_->records = nullptr;
    if (fetches_only) {
      refs_ += count;
      fetches_ += count;
      filtered_->blocks_fit_32_bits = blocks_fit_32_bits(RecordBlocks{records, shift_}, count);
      beyond_narrow_ |= !filtered_->blocks_fit_32_bits;
    } else {
      collect_generic(records, count);
    }
    const References* in = &chunk_;
    for (Level& level : levels_) {
      if (fetches_only && in == &chunk_) {
        level.filter.filter_fetches(records, count, shift_, level.kept);
      } else {
        level.filter.filter(*in, level.kept);
      }
      level.caches.run(level.kept.blocks.data(), level.kept.kinds.data(), level.kept.count, level.kept.invalidates,
                       beyond_narrow_);
      in = &level.kept;
    }
    if (fetches_only) {
      for (std::size_t l = 0; l < levels_.size(); ++l) {
        filtered_->lists[l].blocks = levels_[l].kept.blocks.data();
        filtered_->lists[l].count = levels_[l].kept.count;
      }
      filtered_->records = records;
      filtered_->count = count;
    }
  }

  ResultRow result(std::size_t m) const {
    ResultRow row;
    row.trace = context_.trace;
    row.config = configs_[m];
    row.refs = refs_;
    row.fetches = fetches_;
    row.misses = levels_[where_[m].first].caches.misses(where_[m].second);
    return row;
  }

 private:
  // One set count: its filter, its members' caches, and the references it kept.
  struct Level {
    SetFilter filter;
    PackedCacheBundle caches;
    References kept;
  };

  // Any record: types, spans, other streams.
  void collect_generic(const Record* records, std::size_t count) {
    std::size_t most = 0;
    for (std::size_t i = 0; i < count; ++i) {
      const BlockRange blocks = blocks_of(records[i], context_.form, shift_, aligned_din_);
      most += blocks.count();
    }
    chunk_.make_room(most);
    for (std::size_t i = 0; i < count; ++i) {
      const Record& record = records[i];
      if (is_other_stream(record.tag)) continue;
      ++refs_;
      const BlockRange blocks = blocks_of(record, context_.form, shift_, aligned_din_);
      for (std::uint64_t block = blocks.first;; block = blocks.after(block)) {
        if (record.type <= AccessType::Misc) {
          ++fetches_;
          add(block, PackedReference::Fetch);
        } else if (record.type == AccessType::Invalidate) {
          add(block, PackedReference::Invalidate);
          chunk_.invalidates = true;
        }
        if (block == blocks.last) break;
      }
    }
  }

  void add(std::uint64_t block, PackedReference kind) {
    beyond_narrow_ |= block >= kNarrowBlocks;
    chunk_.blocks[chunk_.count] = block;
    chunk_.kinds[chunk_.count] = kind;
    ++chunk_.count;
  }

  const TraceContext& context_;
  std::vector<Configuration> configs_;
  unsigned shift_;
  bool aligned_din_;
  std::vector<Level> levels_;                                 // fewest sets first
  std::vector<std::pair<std::size_t, std::size_t>> where_;  // per member: its level and index there
  References chunk_;           // the chunk's references, reused
  bool beyond_narrow_ = false;
  std::shared_ptr<GridFilterOutput> filtered_ = std::make_shared<GridFilterOutput>();
  std::uint64_t refs_ = 0;
  std::uint64_t fetches_ = 0;
};

class GridMember final : public ConfigSimulator {
 public:
  GridMember(std::shared_ptr<PolicyGrid> grid, std::size_t index) : grid_(std::move(grid)), index_(index) {}

  void begin_animation_frame(std::uint64_t, std::uint32_t) override {}  // single caches: nothing per frame
  void feed(const Record* records, std::size_t count, std::uint64_t, const PreparedBatch& prepared) override {
    if (index_ == 0) grid_->feed(records, count, prepared);
  }
  ResultRow result() const override { return grid_->result(index_); }
  void append_level_rows(std::vector<LevelRow>&) const override {}  // never per level

 private:
  std::shared_ptr<PolicyGrid> grid_;
  std::size_t index_;
};

}  // namespace

std::string policy_grid_key(const Configuration& config, bool per_level) {
  if (per_level || config.scheme != Scheme::Single || config.fetch != FetchPolicy::Demand ||
      config.prefetch.kind != TreeletPrefetch::None) {
    return {};
  }
  if (misses_as_lru(config.policy, config.assoc)) return {};  // set stacks answer it
  const bool packed_policy = config.policy == ReplacementPolicy::Plru || config.policy == ReplacementPolicy::Srrip ||
                             config.policy == ReplacementPolicy::Brrip || config.policy == ReplacementPolicy::Drrip;
  const bool packed_ways = config.assoc >= 2 && config.assoc <= kMaxPackedWays && std::has_single_bit(config.assoc);
  if (!packed_policy || !packed_ways) return {};
  return fmt::format("single/{}", config.block);
}

PolicyGridSimulators make_policy_grid(const std::vector<Configuration>& members, const TraceContext& context) {
  auto grid = std::make_shared<PolicyGrid>(members, context);
  PolicyGridSimulators made;
  for (std::size_t m = 0; m < members.size(); ++m) made.members.push_back(std::make_unique<GridMember>(grid, m));
  made.filtered = grid->filtered();
  return made;
}

}  // namespace nodetrace::cachesim
