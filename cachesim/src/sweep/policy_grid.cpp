// The policy grid: a chunk's references collected once (repeat filter,
// invalidations in their place), then each member's packed cache run over
// them.
#include "sweep/policy_grid.hpp"

#include <fmt/format.h>

#include <bit>

#include "models/packed_policy_cache.hpp"
#include "models/record_blocks.hpp"

namespace nodetrace::cachesim {

using formats::AccessType;
using formats::Record;

namespace {

// What a chunk asks of every cache, in trace order.
enum class Reference : std::uint8_t {
  Fetch,      // a demand fetch
  Repeated,   // a demand fetch followed by more of the same block
  Invalidate,
};

struct References {
  std::vector<std::uint64_t> blocks;
  std::vector<Reference> kinds;
  std::size_t count = 0;
  bool beyond_narrow = false;  // a block number too large for a 32-bit tag
};

// One member's cache behind a virtual call per chunk.
class GridCache {
 public:
  virtual ~GridCache() = default;
  virtual void run(const References& references) = 0;
  std::uint64_t misses() const { return misses_; }

 protected:
  std::uint64_t misses_ = 0;
};

template <typename State, unsigned kWays>
class GridCacheOf final : public GridCache {
 public:
  explicit GridCacheOf(const CacheGeometry& geometry) : cache_(geometry) {}

  void run(const References& references) override {
    if (references.beyond_narrow && !cache_.wide()) cache_.widen();
    if (cache_.wide()) {
      run_with<std::uint64_t>(references);
    } else {
      run_with<std::uint32_t>(references);
    }
  }

 private:
  template <typename Tag>
  void run_with(const References& references) {
    const std::uint64_t* const blocks = references.blocks.data();
    const Reference* const kinds = references.kinds.data();
    std::uint64_t misses = 0;
    for (std::size_t r = 0; r < references.count; ++r) {
      if (kinds[r] == Reference::Invalidate) [[unlikely]] {
        cache_.template invalidate<Tag>(blocks[r]);
        continue;
      }
      misses += cache_.template access<Tag>(blocks[r], kinds[r] == Reference::Repeated);
    }
    misses_ += misses;
  }

  PackedPolicyCache<State, kWays> cache_;
};

template <template <unsigned> class State>
std::unique_ptr<GridCache> grid_cache_of(const CacheGeometry& geometry) {
  switch (geometry.assoc) {
    case 2: return std::make_unique<GridCacheOf<State<2>, 2>>(geometry);
    case 4: return std::make_unique<GridCacheOf<State<4>, 4>>(geometry);
    case 8: return std::make_unique<GridCacheOf<State<8>, 8>>(geometry);
    default: return std::make_unique<GridCacheOf<State<16>, 16>>(geometry);
  }
}

std::unique_ptr<GridCache> grid_cache(const Configuration& config) {
  const CacheGeometry geometry{config.size, config.block, config.assoc, config.policy};
  validate_geometry(geometry, "cache");
  if (config.policy == ReplacementPolicy::Plru) return grid_cache_of<PackedPlru>(geometry);
  return grid_cache_of<PackedRrip>(geometry);
}

class PolicyGrid {
 public:
  PolicyGrid(const std::vector<Configuration>& configs, const TraceContext& context)
      : context_(context),
        configs_(configs),
        shift_(static_cast<unsigned>(std::countr_zero(configs.front().block))),
        aligned_din_(context.form == formats::RecordForm::Din && configs.front().block >= 4) {
    for (const Configuration& config : configs) caches_.push_back(grid_cache(config));
  }

  void feed(const Record* records, std::size_t count, const PreparedBatch& prepared) {
    if (prepared.demand_only && prepared.span_bits < configs_.front().block) {
      collect_blocks(records, count);
    } else {
      collect_generic(records, count);
    }
    for (const std::unique_ptr<GridCache>& cache : caches_) cache->run(references_);
  }

  ResultRow result(std::size_t m) const {
    ResultRow row;
    row.trace = context_.trace;
    row.config = configs_[m];
    row.refs = refs_;
    row.fetches = fetches_;
    row.misses = caches_[m]->misses();
    return row;
  }

 private:
  void reserve(std::size_t count) {
    if (references_.blocks.size() < count) {
      references_.blocks.resize(count);
      references_.kinds.resize(count);
    }
    references_.count = 0;
  }

  // Every record one demand fetch of one block (din addresses need no
  // rounding: blocks are at least 4 bytes). Without a branch on repeats:
  // a repeat rewrites the last reference as Repeated, another block
  // starts a new one.
  void collect_blocks(const Record* records, std::size_t count) {
    reserve(count);
    refs_ += count;
    fetches_ += count;
    if (count == 0) return;
    std::uint64_t* const blocks = references_.blocks.data();
    Reference* const kinds = references_.kinds.data();
    const unsigned shift = shift_;
    std::uint64_t previous = records[0].address >> shift;
    blocks[0] = previous;
    kinds[0] = Reference::Fetch;
    std::size_t end = 1;
    bool beyond_narrow = previous >= kNarrowBlocks;
    for (std::size_t i = 1; i < count; ++i) {
      const std::uint64_t block = records[i].address >> shift;
      const bool repeat = block == previous;
      end += !repeat;
      blocks[end - 1] = block;
      kinds[end - 1] = repeat ? Reference::Repeated : Reference::Fetch;
      beyond_narrow |= block >= kNarrowBlocks;
      previous = block;
    }
    references_.count = end;
    references_.beyond_narrow |= beyond_narrow;
  }

  // Any record: types, spans, other streams.
  void collect_generic(const Record* records, std::size_t count) {
    std::size_t most = 0;
    for (std::size_t i = 0; i < count; ++i) {
      const BlockRange blocks = blocks_of(records[i], context_.form, shift_, aligned_din_);
      most += blocks.last - blocks.first + 1;
    }
    reserve(most);
    for (std::size_t i = 0; i < count; ++i) {
      const Record& record = records[i];
      if (is_other_stream(record.tag)) continue;
      ++refs_;
      const BlockRange blocks = blocks_of(record, context_.form, shift_, aligned_din_);
      for (std::uint64_t block = blocks.first;; ++block) {
        if (record.type <= AccessType::Misc) {
          ++fetches_;
          add(block, Reference::Fetch);
        } else if (record.type == AccessType::Invalidate) {
          add(block, Reference::Invalidate);
        }
        if (block == blocks.last) break;
      }
    }
  }

  void add(std::uint64_t block, Reference kind) {
    References& refs = references_;
    refs.beyond_narrow |= block >= kNarrowBlocks;
    if (kind == Reference::Fetch && refs.count > 0 && refs.blocks[refs.count - 1] == block &&
        refs.kinds[refs.count - 1] != Reference::Invalidate) {
      refs.kinds[refs.count - 1] = Reference::Repeated;
      return;
    }
    refs.blocks[refs.count] = block;
    refs.kinds[refs.count] = kind;
    ++refs.count;
  }

  const TraceContext& context_;
  std::vector<Configuration> configs_;
  unsigned shift_;
  bool aligned_din_;
  std::vector<std::unique_ptr<GridCache>> caches_;
  References references_;  // the chunk's, reused
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
  if (per_level || config.scheme != Scheme::Single || config.fetch != FetchPolicy::Demand) return {};
  if (misses_as_lru(config.policy, config.assoc)) return {};  // set stacks answer it
  const bool packed_policy = config.policy == ReplacementPolicy::Plru || config.policy == ReplacementPolicy::Srrip ||
                             config.policy == ReplacementPolicy::Brrip || config.policy == ReplacementPolicy::Drrip;
  const bool packed_ways = config.assoc >= 2 && config.assoc <= kMaxPackedWays && std::has_single_bit(config.assoc);
  if (!packed_policy || !packed_ways) return {};
  return fmt::format("single/{}", config.block);
}

std::vector<std::unique_ptr<ConfigSimulator>> make_policy_grid(const std::vector<Configuration>& members,
                                                               const TraceContext& context) {
  auto grid = std::make_shared<PolicyGrid>(members, context);
  std::vector<std::unique_ptr<ConfigSimulator>> simulators;
  for (std::size_t m = 0; m < members.size(); ++m) simulators.push_back(std::make_unique<GridMember>(grid, m));
  return simulators;
}

}  // namespace nodetrace::cachesim
