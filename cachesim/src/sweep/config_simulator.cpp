// The per-configuration simulator, composed of parts: a router (single, or
// split by this frame's K), a low cache model and a high cache model
// (cache_models.hpp), per-level counts or none, and a per-frame hook that
// gives the router its K and clears a retained high cache. The fast loops
// are specialisations of that composition for the common chunk shapes.
#include "sweep/config_simulator.hpp"

#include <fmt/format.h>

#include <bit>
#include <stdexcept>
#include <type_traits>

#include "models/cache_models.hpp"
#include "models/record_blocks.hpp"
#include "dinero/prefetching_cache.hpp"

namespace nodetrace::cachesim {

using formats::AccessType;
using formats::Record;
using formats::Tag;

namespace {

// Routers: which cache a record of a level goes to.
struct SingleRouter {
  static constexpr bool kSplit = false;
  std::uint32_t split_level = 0;  // unused
  bool high(Tag) const { return false; }
};
struct SplitRouter {
  static constexpr bool kSplit = true;
  std::uint32_t split_level = 0;  // K of the current animation frame
  bool high(Tag tag) const { return tag < split_level; }
};

// Per-level counts (--per-level) or none.
struct LevelCounts {
  static constexpr bool kCounting = true;
  std::vector<std::uint64_t> refs;
  std::vector<std::uint64_t> misses;
  void count_ref(Tag tag) {
    if (tag >= refs.size()) {
      refs.resize(tag + 1u, 0);
      misses.resize(tag + 1u, 0);
    }
    ++refs[tag];
  }
  void count_miss(Tag tag) { ++misses[tag]; }
};
struct NoLevelCounts {
  static constexpr bool kCounting = false;
  std::vector<std::uint64_t> refs;
  std::vector<std::uint64_t> misses;
  void count_ref(Tag) {}
  void count_miss(Tag) {}
};

struct Counters {
  std::uint64_t refs = 0;
  std::uint64_t fetches = 0;
  std::uint64_t high_refs = 0;
  std::uint64_t high_misses = 0;
  std::uint64_t high_loads = 0;
  std::uint64_t low_refs = 0;
  std::uint64_t low_misses = 0;
};

template <typename Model>
constexpr bool kTable = std::is_same_v<Model, DirectMappedTable>;
// A model that prefetches needs each fetch's access type.
template <typename Model>
constexpr bool kTyped = std::is_same_v<Model, PrefetchingCache>;

// The slot of `block` in the low or the high table (`high` 0 or 1) by
// arithmetic: a branch on the level would mispredict at every change.
inline std::uint64_t& pick_slot(std::uint64_t high, std::uint64_t block, std::uint64_t* low_slots,
                                std::uint64_t low_mask, std::uint64_t* high_slots,
                                std::uint64_t high_mask) {
  const std::uint64_t select = std::uint64_t{0} - high;  // all ones when high
  const auto low_base = reinterpret_cast<std::uintptr_t>(low_slots);
  const auto high_base = reinterpret_cast<std::uintptr_t>(high_slots);
  auto* const slots = reinterpret_cast<std::uint64_t*>(low_base ^ ((low_base ^ high_base) & select));
  return slots[block & (low_mask ^ ((low_mask ^ high_mask) & select))];
}

template <typename Router, typename Low, typename High, typename Levels>
class Simulator final : public ConfigSimulator {
  static constexpr bool kRetain = std::is_same_v<High, RetainSet>;
  // Every cache a slot in a table: the fast loop picks the table without
  // a branch on the record's level.
  static constexpr bool kFlat =
      kTable<Low> && (!Router::kSplit || kTable<High> || kRetain);
  // Split configurations of this shape but other K can share one loop.
  static constexpr bool kTogether = kFlat && Router::kSplit && !Levels::kCounting;

  template <typename, typename, typename, typename>
  friend class Simulator;

 public:
  Simulator(const Configuration& config, std::uint32_t split_level, const TraceContext& context,
            Low low, High high)
      : config_(config),
        context_(context),
        shift_(static_cast<unsigned>(std::countr_zero(config.block))),
        aligned_din_(context.form == formats::RecordForm::Din && config.block >= 4),
        low_(std::move(low)),
        high_(std::move(high)) {
    router_.split_level = split_level;
  }

  // The per-frame hook.
  void begin_animation_frame(std::uint64_t animation_frame, std::uint32_t split_level) override {
    animation_frame_ = animation_frame;
    router_.split_level = split_level;
    if constexpr (kRetain) high_.begin_animation_frame();
  }

  void begin_treelets(const formats::TreeletMap* map) override {
    cachesim::begin_treelets(low_, map);
    cachesim::begin_treelets(high_, map);
  }

  void feed(const Record* records, std::size_t count, std::uint64_t first_record,
            const PreparedBatch& prepared) override {
    if constexpr (kTogether) {
      if (fed_by_leader_) return;
      if (!together_.empty()) {
        if (prepared.demand_only && prepared.span_bits < config_.block) {
          feed_flat_together(records, count, first_record);
        } else {
          for (Simulator* member : together_) member->feed_own(records, count, first_record, prepared);
        }
        return;
      }
    }
    feed_own(records, count, first_record, prepared);
  }

  // `members` (this one first, at most kMaxTogether) are fed by this one's
  // feed(); theirs then do nothing.
  void feed_together(const std::vector<Simulator*>& members)
    requires kTogether
  {
    together_ = members;
    for (Simulator* member : members) member->fed_by_leader_ = member != this;
  }

  ResultRow result() const override {
    ResultRow row;
    row.trace = context_.trace;
    row.config = config_;
    const Counters& c = counters_;
    const std::uint64_t high_misses = c.high_misses + deferred_misses(high_);
    const std::uint64_t low_misses = c.low_misses + deferred_misses(low_);
    row.refs = c.refs;
    row.fetches = c.fetches;
    row.misses = high_misses + low_misses;
    if constexpr (Router::kSplit) {
      row.split_level = router_.split_level;
      row.high_refs = c.high_refs;
      row.high_misses = high_misses;
      if constexpr (kRetain) row.high_loads = c.high_loads;
      row.low_refs = c.low_refs;
      row.low_misses = low_misses;
    }
    if (config_.prefetch.kind != TreeletPrefetch::None) {
      PrefetchColumns prefetch;
      prefetch.spec = config_.prefetch;
      prefetch.counts = prefetch_counts(low_);
      prefetch.counts += prefetch_counts(high_);
      row.prefetch = prefetch;
    }
    return row;
  }

  void append_level_rows(std::vector<LevelRow>& rows) const override {
    for (std::size_t level = 0; level < levels_.refs.size(); ++level) {
      if (levels_.refs[level] == 0) continue;
      rows.push_back(LevelRow{context_.trace, config_, 0,
                              static_cast<std::uint32_t>(level), levels_.refs[level],
                              levels_.misses[level]});
    }
  }

 private:
  void feed_own(const Record* records, std::size_t count, std::uint64_t first_record,
                const PreparedBatch& prepared) {
    if (!Levels::kCounting && !kTyped<Low> && prepared.demand_only && prepared.span_bits < config_.block) {
      if constexpr (kFlat) {
        feed_flat(records, count, first_record);
      } else {
        feed_blocks(records, count, first_record);
      }
      return;
    }
    feed_generic(records, count, first_record);
  }

  // Fast path, every cache a table: one demand fetch of one block per
  // record, no branch but the rare first touch of a retained block.
  // Din addresses need no rounding here: blocks are at least 4 bytes.
  void feed_flat(const Record* records, std::size_t count, std::uint64_t first_record)
    requires kFlat
  {
    const unsigned shift = shift_;
    std::uint64_t* const low_slots = low_.slots();
    const std::uint64_t low_mask = low_.mask();
    std::uint64_t* high_slots = low_slots;
    std::uint64_t high_mask = low_mask;
    if constexpr (kRetain) {
      high_slots = high_.filter().slots();
      high_mask = high_.filter().mask();
    } else if constexpr (Router::kSplit) {
      high_slots = high_.slots();
      high_mask = high_.mask();
    }
    const Router router = router_;
    std::uint64_t high_refs = 0;
    std::uint64_t high_misses = 0;
    std::uint64_t low_misses = 0;
    for (std::size_t i = 0; i < count; ++i) {
      const std::uint64_t block = records[i].address >> shift;
      const std::uint64_t high = router.high(records[i].tag);
      std::uint64_t& slot = pick_slot(high, block, low_slots, low_mask, high_slots, high_mask);
      const std::uint64_t differ = slot != block;
      slot = block;
      high_refs += high;
      low_misses += differ & (high ^ 1);
      if constexpr (kRetain) {
        std::uint64_t first_touch = differ & high;
        // Hides that both are 0 / 1, or GCC branches on `high` first (a
        // misprediction for every change of level).
        asm("" : "+r"(first_touch));
        if (first_touch != 0) [[unlikely]] {
          if (high_.insert_after_filter(block)) {
            high_misses += count_load(first_record + i + 1);
          }
        }
      } else {
        high_misses += differ & high;
      }
    }
    count_fast(count, high_refs, high_misses, low_misses);
  }

  // feed_flat of several members, each with its own K, low table and high
  // table or retain set: each record is read once.
  void feed_flat_together(const Record* records, std::size_t count, std::uint64_t first_record)
    requires kTogether
  {
    const std::size_t members = std::min(together_.size(), kMaxTogether);
    std::uint32_t split_levels[kMaxTogether];
    std::uint64_t* low_slots[kMaxTogether];
    std::uint64_t low_masks[kMaxTogether];
    std::uint64_t* high_slots[kMaxTogether];
    std::uint64_t high_masks[kMaxTogether];
    std::uint64_t high_refs[kMaxTogether] = {};
    std::uint64_t high_misses[kMaxTogether] = {};
    std::uint64_t low_misses[kMaxTogether] = {};
    for (std::size_t m = 0; m < members; ++m) {
      Simulator& member = *together_[m];
      split_levels[m] = member.router_.split_level;
      low_slots[m] = member.low_.slots();
      low_masks[m] = member.low_.mask();
      if constexpr (kRetain) {
        high_slots[m] = member.high_.filter().slots();
        high_masks[m] = member.high_.filter().mask();
      } else {
        high_slots[m] = member.high_.slots();
        high_masks[m] = member.high_.mask();
      }
    }
    const unsigned shift = shift_;
    for (std::size_t i = 0; i < count; ++i) {
      const std::uint64_t block = records[i].address >> shift;
      const Tag tag = records[i].tag;
      for (std::size_t m = 0; m < members; ++m) {
        const std::uint64_t high = tag < split_levels[m];
        // Branches here measured faster than pick_slot's arithmetic.
        std::uint64_t* const slots = high ? high_slots[m] : low_slots[m];
        std::uint64_t& slot = slots[block & (high ? high_masks[m] : low_masks[m])];
        const std::uint64_t differ = slot != block;
        slot = block;
        high_refs[m] += high;
        low_misses[m] += differ & (high ^ 1);
        if constexpr (kRetain) {
          std::uint64_t first_touch = differ & high;
          asm("" : "+r"(first_touch));  // see feed_flat
          if (first_touch != 0) [[unlikely]] {
            Simulator& member = *together_[m];
            if (member.high_.insert_after_filter(block)) {
              high_misses[m] += member.count_load(first_record + i + 1);
            }
          }
        } else {
          high_misses[m] += differ & high;
        }
      }
    }
    for (std::size_t m = 0; m < members; ++m) {
      together_[m]->count_fast(count, high_refs[m], high_misses[m], low_misses[m]);
    }
  }

  // Fast path with a set-associative cache: one block per record.
  // Din addresses need no rounding here: blocks are at least 4 bytes.
  void feed_blocks(const Record* records, std::size_t count, std::uint64_t first_record) {
    const unsigned shift = shift_;
    if constexpr (!Router::kSplit && requires { low_.access_blocks_of(records, count, shift); }) {
      // A treelet prefetcher's loop of its own.
      count_fast(count, 0, 0, low_.access_blocks_of(records, count, shift));
      return;
    }
    std::uint64_t high_refs = 0;
    std::uint64_t high_misses = 0;
    std::uint64_t low_misses = 0;
    for (std::size_t i = 0; i < count; ++i) {
      const std::uint64_t block = records[i].address >> shift;
      if (router_.high(records[i].tag)) {
        ++high_refs;
        high_misses += high_access(block, first_record + i + 1);
      } else {
        low_misses += low_.access(block);
      }
    }
    count_fast(count, high_refs, high_misses, low_misses);
  }

  void count_fast(std::uint64_t count, std::uint64_t high_refs, std::uint64_t high_misses,
                  std::uint64_t low_misses) {
    counters_.refs += count;
    counters_.fetches += count;
    counters_.high_refs += high_refs;
    counters_.low_refs += count - high_refs;
    counters_.high_misses += high_misses;
    counters_.low_misses += low_misses;
  }

  // A high-level fetch; returns whether it counts as a miss.
  bool high_access(std::uint64_t block, std::uint64_t record_number) {
    if constexpr (kRetain) {
      return high_.access(block) && count_load(record_number);
    } else {
      return high_.access(block);
    }
  }

  // A new load of the retained high cache: whether it counts as a miss.
  bool count_load(std::uint64_t record_number) {
    ++counters_.high_loads;
    if (high_.count() > high_.capacity()) {
      throw_high_levels_do_not_fit(context_, config_, record_number, router_.split_level,
                                   animation_frame_, high_.capacity());
    }
    return config_.count_loads;
  }

  // Any record: types, spans, other streams, per-level counts.
  void feed_generic(const Record* records, std::size_t count, std::uint64_t first_record) {
    for (std::size_t i = 0; i < count; ++i) {
      const Record& record = records[i];
      const Tag tag = record.tag;
      if (is_other_stream(tag)) continue;
      const BlockRange blocks = blocks_of(record, context_.form, shift_, aligned_din_);
      ++counters_.refs;
      const bool high = router_.high(tag);
      if (high) {
        ++counters_.high_refs;
      } else {
        ++counters_.low_refs;
      }
      levels_.count_ref(tag);
      const AccessType type = record.type;
      for (std::uint64_t block = blocks.first;; block = blocks.after(block)) {
        if (type <= AccessType::Misc) {
          ++counters_.fetches;
          bool miss;
          if (high) {
            miss = high_access(block, first_record + i + 1);
            counters_.high_misses += miss;
          } else {
            if constexpr (kTyped<Low>) {
              miss = low_.access(block, type);
            } else {
              miss = low_.access(block);
            }
            counters_.low_misses += miss;
          }
          if (miss) levels_.count_miss(tag);
        } else if (type == AccessType::Invalidate) {
          // A retained high cache keeps its blocks for the frame.
          if (!high) {
            low_.invalidate(block);
          } else if constexpr (!kRetain) {
            high_.invalidate(block);
          }
        }
        if (block == blocks.last) break;
      }
    }
  }

  Configuration config_;
  const TraceContext& context_;
  unsigned shift_;
  bool aligned_din_;
  Router router_;
  Low low_;
  High high_;
  Levels levels_;
  std::uint64_t animation_frame_ = 0;
  Counters counters_;
  std::vector<Simulator*> together_;  // feed_together's members, this one first
  bool fed_by_leader_ = false;
};

template <typename Router, typename Low, typename High>
std::unique_ptr<ConfigSimulator> compose(const Configuration& config, std::uint32_t split_level,
                                         const TraceContext& context, bool per_level, Low low,
                                         High high) {
  if (per_level) {
    return std::make_unique<Simulator<Router, Low, High, LevelCounts>>(
        config, split_level, context, std::move(low), std::move(high));
  }
  return std::make_unique<Simulator<Router, Low, High, NoLevelCounts>>(
      config, split_level, context, std::move(low), std::move(high));
}

// The low side chosen, the high side next.
template <typename Low>
std::unique_ptr<ConfigSimulator> with_high(const Configuration& config, std::uint32_t split_level,
                                           const TraceContext& context, bool per_level, Low low,
                                           const OptSource& high_opt) {
  if (config.scheme == Scheme::Single) {
    return compose<SingleRouter>(config, split_level, context, per_level, std::move(low),
                                 NoCache{});
  }
  if (config.high_policy == HighPolicy::Retain) {
    return compose<SplitRouter>(config, split_level, context, per_level, std::move(low),
                                RetainSet(config.high_size / config.block));
  }
  return with_cache_model({config.high_size, config.block, config.high_assoc, config.policy}, high_opt, [&](auto high) {
    using High = decltype(high);
    if constexpr (std::is_same_v<High, DirectMappedTable> || std::is_same_v<High, SetAssociativeCache>) {
      return compose<SplitRouter>(config, split_level, context, per_level, std::move(low), std::move(high));
    } else {
      return compose<SplitRouter>(config, split_level, context, per_level, std::move(low),
                                  AnyCache(std::move(high)));
    }
  });
}

template <typename High>
std::vector<std::unique_ptr<ConfigSimulator>> together(const std::vector<Configuration>& configs,
                                                       const std::vector<std::uint32_t>& split_levels,
                                                       const TraceContext& context) {
  using Member = Simulator<SplitRouter, DirectMappedTable, High, NoLevelCounts>;
  std::vector<std::unique_ptr<ConfigSimulator>> simulators;
  std::vector<Member*> members;
  for (std::size_t m = 0; m < configs.size(); ++m) {
    const Configuration& config = configs[m];
    auto high = [&] {
      if constexpr (std::is_same_v<High, RetainSet>) {
        return RetainSet(config.high_size / config.block);
      } else {
        return DirectMappedTable(config.high_size / config.block);
      }
    };
    auto member = std::make_unique<Member>(config, split_levels[m], context,
                                           DirectMappedTable(config.low_size / config.block), high());
    members.push_back(member.get());
    simulators.push_back(std::move(member));
  }
  members.front()->feed_together(members);
  return simulators;
}

}  // namespace

std::string together_key(const Configuration& config, bool per_level) {
  if (per_level || config.scheme != Scheme::Split || config.assoc != 1 ||
      config.policy == ReplacementPolicy::Opt || config.fetch != FetchPolicy::Demand ||
      config.prefetch.kind != TreeletPrefetch::None) {
    return {};
  }
  if (config.high_policy == HighPolicy::Cache && config.high_assoc != 1) return {};
  return fmt::format("{}/{}", config.block, high_policy_name(config.high_policy));
}

std::vector<std::unique_ptr<ConfigSimulator>> make_together(
    const std::vector<Configuration>& configs, const std::vector<std::uint32_t>& split_levels,
    const TraceContext& context) {
  if (configs.size() > kMaxTogether) throw std::logic_error("make_together: too many members");
  if (configs.front().high_policy == HighPolicy::Retain) {
    return together<RetainSet>(configs, split_levels, context);
  }
  return together<DirectMappedTable>(configs, split_levels, context);
}

namespace {

// The stream of the opt caches that see the fetches `key` names: the first
// to ask records it.
// Only a cache that is opt may ask: a cache of another policy that asked
// first would be taken for the recorder and never record, and every opt
// cache of its stream would count MIN over no fetches.
OptSource opt_source(OptStreams* streams, const std::string& key) {
  if (streams == nullptr) return {};
  std::shared_ptr<SharedOptStream>& shared = (*streams)[key];
  if (shared) return {shared, false};
  shared = std::make_shared<SharedOptStream>();
  return {shared, true};
}

}  // namespace

std::unique_ptr<ConfigSimulator> make_simulator(const Configuration& config,
                                                std::uint32_t split_level,
                                                const TraceContext& context, bool per_level,
                                                OptStreams* opt_streams) {
  const CacheGeometry low{config.scheme == Scheme::Split ? config.low_size : config.size,
                          config.block, config.assoc, config.policy};
  // Caches of one block size behind the same router see the same fetches:
  // single, or split with the same K in every animation frame.
  const std::string k_rule = config.split_level ? std::to_string(*config.split_level)
                                                : fmt::format("auto{}", config.high_size);
  const bool opt = config.policy == ReplacementPolicy::Opt;
  const bool high_is_opt = opt && config.scheme == Scheme::Split && config.high_policy == HighPolicy::Cache;
  const OptSource high_opt =
      high_is_opt ? opt_source(opt_streams, fmt::format("high/{}/{}", config.block, k_rule)) : OptSource{};
  if (config.prefetch.kind != TreeletPrefetch::None) {
    return with_treelet_prefetcher(low, config.prefetch.bytes, [&](auto low_model) {
      // `treelet`: the high cache under `cache` prefetches too; a retained
      // one loads each block once per frame whatever is prefetched.
      if (config.scheme == Scheme::Split && config.high_policy == HighPolicy::Cache &&
          config.prefetch.kind == TreeletPrefetch::Treelet) {
        return with_treelet_prefetcher(
            {config.high_size, config.block, config.high_assoc, config.policy}, config.prefetch.bytes,
            [&](auto high_model) {
              return compose<SplitRouter>(config, split_level, context, per_level, std::move(low_model),
                                          AnyCache(std::move(high_model)));
            });
      }
      return with_high(config, split_level, context, per_level, std::move(low_model), high_opt);
    });
  }
  if (config.fetch != FetchPolicy::Demand) {
    return with_high(config, split_level, context, per_level,
                     PrefetchingCache(low, config.fetch, config.prefetch_distance), high_opt);
  }
  const OptSource low_opt =
      !opt ? OptSource{}
           : opt_source(opt_streams, config.scheme == Scheme::Single
                                         ? fmt::format("single/{}", config.block)
                                         : fmt::format("low/{}/{}", config.block, k_rule));
  return with_cache_model(low, low_opt, [&](auto model) {
    return with_high(config, split_level, context, per_level, std::move(model), high_opt);
  });
}

}  // namespace nodetrace::cachesim
