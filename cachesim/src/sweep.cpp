#include "nodetrace/cachesim/sweep.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <cctype>
#include <charconv>
#include <limits>

#include "nodetrace/formats/error.hpp"

namespace nodetrace::cachesim {

using formats::AccessType;
using formats::FormatError;
using formats::Record;
using formats::Tag;
using formats::UsageError;

// ---------------------------------------------------------------------------
// Per-configuration simulators.

class ConfigSimulator {
 public:
  virtual ~ConfigSimulator() = default;
  // An animation frame begins; `split_level` is its K (split only).
  virtual void begin_frame(std::uint64_t animation_frame, std::uint32_t split_level) = 0;
  // `first_record`: 0-based number of records[0] in the trace (for errors).
  virtual void feed(const Record* records, std::size_t count, std::uint64_t first_record,
                    const PreparedBatch& prepared) = 0;
  virtual ResultRow result() const = 0;
  virtual void append_level_rows(std::vector<LevelRow>& rows) const = 0;

  // Configurations with equal group keys (same kind, block, rule for K, all
  // direct mapped) can be simulated together by one loop over the records:
  // the leader's feed_group(members) is then feed() of each member, on chunks
  // of demand fetches of one block each (returns false for other chunks,
  // which the members take one by one). Empty key: no grouping.
  virtual std::string group_key() const { return {}; }
  virtual bool feed_group(const std::vector<ConfigSimulator*>& members, const Record* records,
                          std::size_t count, std::uint64_t first_record,
                          const PreparedBatch& prepared) {
    (void)members, (void)records, (void)count, (void)first_record, (void)prepared;
    return false;
  }
};

namespace {

// The distinct high-level blocks touched in the current animation frame
// (`retain`): an open-addressing set cleared in O(1) per frame by an epoch.
class RetainedBlocks {
 public:
  explicit RetainedBlocks(std::uint64_t capacity_blocks) : capacity_(capacity_blocks) {
    const std::uint64_t slots = std::bit_ceil(std::max<std::uint64_t>(16, 2 * (capacity_ + 1)));
    keys_.resize(slots);
    stamps_.assign(slots, 0);
    mask_ = slots - 1;
    hash_shift_ = 64 - static_cast<unsigned>(std::countr_zero(slots));
  }

  std::uint64_t capacity() const { return capacity_; }
  std::uint64_t count() const { return count_; }

  void clear() {
    count_ = 0;
    last_ = NodeCache::kInvalid;
    if (++epoch_ == 0) {
      std::fill(stamps_.begin(), stamps_.end(), 0);
      epoch_ = 1;
    }
  }

  // True when `block` is new this frame.
  bool insert(std::uint64_t block) {
    if (block == last_) return false;
    last_ = block;
    std::uint64_t slot = (block * 0x9E3779B97F4A7C15ull) >> hash_shift_;
    while (true) {
      if (stamps_[slot] != epoch_) {
        stamps_[slot] = epoch_;
        keys_[slot] = block;
        ++count_;
        return true;
      }
      if (keys_[slot] == block) return false;
      slot = (slot + 1) & mask_;
    }
  }

 private:
  std::uint64_t capacity_;
  std::vector<std::uint64_t> keys_;
  std::vector<std::uint32_t> stamps_;
  std::uint32_t epoch_ = 1;
  std::uint64_t mask_ = 0;
  unsigned hash_shift_ = 0;
  std::uint64_t count_ = 0;
  std::uint64_t last_ = NodeCache::kInvalid;
};

constexpr bool is_other_stream(Tag tag) {
  return tag == formats::kTagPrimitiveList || tag == formats::kTagTriangle;
}

struct Counters {
  std::uint64_t refs = 0;
  std::uint64_t fetches = 0;
  std::uint64_t high_refs = 0;
  std::uint64_t high_misses = 0;
  std::uint64_t high_loads = 0;
  std::uint64_t low_refs = 0;
  std::uint64_t low_misses = 0;
};

// kSplit: route by level; kRetain: high part retained per animation frame;
// kPerLevel: count per level; kAlignedDin: din records (4 bytes at a multiple
// of 4) with blocks of at least 4 bytes, so every record is one block.
template <bool kSplit, bool kRetain, bool kPerLevel, bool kAlignedDin>
class Simulator final : public ConfigSimulator {
 public:
  Simulator(const NodeCacheConfig& config, std::uint32_t split_level, const TraceContext& context)
      : config_(config),
        context_(context),
        split_level_(split_level),
        retained_(kRetain ? config.high_size / config.block : 0) {
    const CacheGeometry low{kSplit ? config.low_size : config.size, config.block, config.assoc,
                                config.policy};
    block_shift_ = static_cast<unsigned>(std::countr_zero(config.block));
    // Direct-mapped caches (and the retain filter) live in one flat table:
    // low sets first, then the high part, so the fast loop picks either with
    // arithmetic instead of a branch on the record's level.
    std::uint64_t low_sets = 0;
    if (low.assoc == 1) {
      low_sets = low.size / low.block;
    } else {
      low_cache_.emplace(low);
    }
    std::uint64_t high_sets = 0;
    if constexpr (kRetain) {
      high_sets = std::bit_ceil(std::max<std::uint64_t>(64, 4 * (config.high_size / config.block)));
    } else if constexpr (kSplit) {
      const CacheGeometry high{config.high_size, config.block, config.high_assoc,
                                   config.policy};
      if (high.assoc == 1) {
        high_sets = high.size / high.block;
      } else {
        high_cache_.emplace(high, 0x5eed + 1);
      }
    }
    low_direct_ = low_sets > 0;
    high_direct_ = kRetain || high_sets > 0;
    low_mask_ = low_sets > 0 ? low_sets - 1 : 0;
    high_mask_ = high_sets > 0 ? high_sets - 1 : 0;
    high_offset_ = low_sets;
    // One more slot at the end: where a group's loop writes the low caches'
    // updates for high-level records (never read as a cache line).
    dummy_slot_ = low_sets + high_sets;
    table_.assign(dummy_slot_ + 1, NodeCache::kInvalid);
  }

  void begin_frame(std::uint64_t animation_frame, std::uint32_t split_level) override {
    animation_frame_ = animation_frame;
    split_level_ = split_level;
    if constexpr (kRetain) {
      retained_.clear();
      std::fill(table_.begin() + static_cast<std::ptrdiff_t>(high_offset_), table_.end(),
                NodeCache::kInvalid);
    }
  }

  void feed(const Record* records, std::size_t count, std::uint64_t first_record,
            const PreparedBatch& prepared) override {
    if (!kPerLevel && prepared.demand_only && prepared.span_bits < config_.block) {
      if (low_direct_ && (!kSplit || high_direct_)) {
        feed_flat(records, count, first_record);
      } else {
        feed_blocks(records, count, first_record);
      }
      return;
    }
    feed_generic(records, count, first_record);
  }

  std::string group_key() const override {
    if constexpr (kPerLevel || (kSplit && !kRetain)) {
      return {};
    } else {
      if (!low_direct_) return {};
      // Members must share K in every animation frame: the same given K, or
      // auto for the same high-cache size.
      const std::string k_rule = config_.split_level
                                     ? std::to_string(*config_.split_level)
                                     : fmt::format("auto{}", kSplit ? config_.high_size : 0);
      return fmt::format("{}/{}/{}/{}/{}/{}", kSplit, kRetain, kAlignedDin, config_.block, k_rule,
                         config_.count_loads);
    }
  }

  bool feed_group(const std::vector<ConfigSimulator*>& members, const Record* records,
                  std::size_t count, std::uint64_t first_record,
                  const PreparedBatch& prepared) override {
    if constexpr (kPerLevel || (kSplit && !kRetain)) {
      (void)members, (void)records, (void)count, (void)first_record, (void)prepared;
      return false;
    } else {
      if (!prepared.demand_only || prepared.span_bits >= config_.block) return false;
      group_.clear();
      for (ConfigSimulator* member : members) group_.push_back(static_cast<Simulator*>(member));
      feed_group_flat(records, count, first_record);
      return true;
    }
  }

  ResultRow result() const override {
    ResultRow row;
    row.trace = context_.trace;
    row.config = config_;
    const Counters& c = counters_;
    row.refs = c.refs;
    row.fetches = c.fetches;
    row.misses = c.high_misses + c.low_misses;
    if constexpr (kSplit) {
      row.split_level = split_level_;
      row.high_refs = c.high_refs;
      row.high_misses = c.high_misses;
      if constexpr (kRetain) row.high_loads = c.high_loads;
      row.low_refs = c.low_refs;
      row.low_misses = c.low_misses;
    }
    return row;
  }

  void append_level_rows(std::vector<LevelRow>& rows) const override {
    for (std::size_t level = 0; level < level_refs_.size(); ++level) {
      if (level_refs_[level] == 0) continue;
      rows.push_back(LevelRow{context_.trace, config_.scheme, config_.size,
                              static_cast<std::uint32_t>(level), level_refs_[level],
                              level_misses_[level]});
    }
  }

 private:
  // Fast path, every cache direct mapped: one demand fetch of one block per
  // record, no branch but the rare first touch of a retained block.
  // Din addresses need no rounding here: blocks are at least 4 bytes.
  void feed_flat(const Record* records, std::size_t count, std::uint64_t first_record) {
    const unsigned shift = block_shift_;
    std::uint64_t* const table = table_.data();
    const std::uint64_t low_mask = low_mask_;
    const std::uint64_t mask_difference = low_mask_ ^ high_mask_;
    const std::uint64_t high_offset = high_offset_;
    const std::uint64_t split_level = split_level_;
    std::uint64_t high_refs = 0;
    std::uint64_t high_misses = 0;
    std::uint64_t low_misses = 0;
    for (std::size_t i = 0; i < count; ++i) {
      const std::uint64_t block = records[i].address >> shift;
      std::uint64_t high = 0;
      if constexpr (kSplit) high = records[i].tag < split_level;
      const std::uint64_t select = std::uint64_t{0} - high;  // all ones when high
      const std::uint64_t index =
          (block & (low_mask ^ (mask_difference & select))) + (high_offset & select);
      const std::uint64_t differ = table[index] != block;
      table[index] = block;
      high_refs += high;
      low_misses += differ & (high ^ 1);
      if constexpr (kRetain) {
        std::uint64_t first_touch = differ & high;
        // Hides that both are 0 / 1, or GCC branches on `high` first (a
        // misprediction for every change of level).
        asm("" : "+r"(first_touch));
        if (first_touch != 0) [[unlikely]] {
          if (retain_insert(block, first_record + i + 1)) high_misses += config_.count_loads;
        }
      } else {
        high_misses += differ & high;
      }
    }
    count_fast(count, high_refs, high_misses, low_misses);
  }

  // feed_flat for a group: the record and its level are read once; each
  // member's low cache is one slot update (high-level records write the
  // dummy slot); under retain the leader's filter stands for all, and a first
  // touch is recorded in every member (whose loads are then equal).
  void feed_group_flat(const Record* records, std::size_t count, std::uint64_t first_record) {
    constexpr std::size_t kMaxGroup = 8;
    const std::size_t group_size = std::min(group_.size(), kMaxGroup);
    std::uint64_t* tables[kMaxGroup];
    std::uint64_t masks[kMaxGroup];
    std::uint64_t dummies[kMaxGroup];
    std::uint64_t low_misses[kMaxGroup] = {};
    for (std::size_t g = 0; g < group_size; ++g) {
      tables[g] = group_[g]->table_.data();
      masks[g] = group_[g]->low_mask_;
      dummies[g] = group_[g]->dummy_slot_;
    }
    const unsigned shift = block_shift_;
    std::uint64_t* const filter = table_.data() + high_offset_;
    const std::uint64_t filter_mask = high_mask_;
    const std::uint64_t split_level = split_level_;
    std::uint64_t high_refs = 0;
    for (std::size_t i = 0; i < count; ++i) {
      const std::uint64_t block = records[i].address >> shift;
      std::uint64_t high = 0;
      if constexpr (kSplit) high = records[i].tag < split_level;
      const std::uint64_t select = std::uint64_t{0} - high;  // all ones when high
      for (std::size_t g = 0; g < group_size; ++g) {
        const std::uint64_t index = (block & masks[g] & ~select) | (dummies[g] & select);
        const std::uint64_t differ = tables[g][index] != block;
        tables[g][index] = block;
        low_misses[g] += differ & (high ^ 1);
      }
      if constexpr (kRetain) {
        high_refs += high;
        std::uint64_t& slot = filter[block & filter_mask];
        std::uint64_t first_touch = static_cast<std::uint64_t>(slot != block) & high;
        asm("" : "+r"(first_touch));  // see feed_flat
        if (first_touch != 0) [[unlikely]] {
          for (std::size_t g = 0; g < group_size; ++g) group_[g]->group_first_touch(block, first_record + i + 1);
        }
      }
    }
    for (std::size_t g = 0; g < group_size; ++g) {
      group_[g]->count_fast(count, high_refs, group_[g]->pending_high_misses_, low_misses[g]);
      group_[g]->pending_high_misses_ = 0;
    }
  }

  // A retained block first seen by the group's leader this frame.
  [[gnu::noinline]] void group_first_touch(std::uint64_t block, std::uint64_t record_number) {
    table_[high_offset_ + (block & high_mask_)] = block;
    if (retain_insert(block, record_number)) pending_high_misses_ += config_.count_loads;
  }

  // Fast path with a set-associative cache: one block per record.
  // Din addresses need no rounding here: blocks are at least 4 bytes.
  void feed_blocks(const Record* records, std::size_t count, std::uint64_t first_record) {
    const unsigned shift = block_shift_;
    std::uint64_t high_refs = 0;
    std::uint64_t high_misses = 0;
    std::uint64_t low_misses = 0;
    for (std::size_t i = 0; i < count; ++i) {
      const std::uint64_t block = records[i].address >> shift;
      bool high = false;
      if constexpr (kSplit) high = records[i].tag < split_level_;
      if (high) {
        ++high_refs;
        high_misses += high_access(block, first_record + i + 1);
      } else {
        low_misses += low_access(block);
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

  bool low_access(std::uint64_t block) {
    if (!low_direct_) return low_cache_->access(block);
    std::uint64_t& slot = table_[block & low_mask_];
    const bool miss = slot != block;
    slot = block;
    return miss;
  }

  // A high-level fetch; returns whether it counts as a miss.
  bool high_access(std::uint64_t block, std::uint64_t record_number) {
    if constexpr (kRetain) {
      std::uint64_t& filter = table_[high_offset_ + (block & high_mask_)];
      if (filter == block) return false;
      filter = block;
      return retain_insert(block, record_number) && config_.count_loads;
    } else {
      if (!high_direct_) return high_cache_->access(block);
      std::uint64_t& slot = table_[high_offset_ + (block & high_mask_)];
      const bool miss = slot != block;
      slot = block;
      return miss;
    }
  }

  // A block missing from the retain filter: true when it is a new load.
  [[gnu::noinline]] bool retain_insert(std::uint64_t block, std::uint64_t record_number) {
    if (!retained_.insert(block)) return false;
    ++counters_.high_loads;
    if (retained_.count() > retained_.capacity()) throw_does_not_fit(record_number);
    return true;
  }

  void invalidate(bool high, std::uint64_t block) {
    if (!high) {
      if (!low_direct_) {
        low_cache_->invalidate(block);
      } else if (std::uint64_t& slot = table_[block & low_mask_]; slot == block) {
        slot = NodeCache::kInvalid;
      }
    } else if constexpr (!kRetain) {
      if (!high_direct_) {
        high_cache_->invalidate(block);
      } else if (std::uint64_t& slot = table_[high_offset_ + (block & high_mask_)];
                 slot == block) {
        slot = NodeCache::kInvalid;
      }
    }
  }

  // Any record: types, spans, other streams, per-level counts.
  void feed_generic(const Record* records, std::size_t count, std::uint64_t first_record) {
    const unsigned shift = block_shift_;
    for (std::size_t i = 0; i < count; ++i) {
      const Record& record = records[i];
      const Tag tag = record.tag;
      if (is_other_stream(tag)) continue;
      std::uint64_t first_block;
      std::uint64_t last_block;
      if constexpr (kAlignedDin) {
        first_block = record.address >> shift;
        last_block = first_block;
      } else {
        const Record view = formats::dinero_view(record, context_.form);
        first_block = view.address >> shift;
        const std::uint64_t span = view.size == 0 ? 0 : view.size - 1;
        last_block = (view.address + span) >> shift;
        if (last_block < first_block) last_block = first_block;  // wraps past 2^64
      }
      ++counters_.refs;
      bool high = false;
      if constexpr (kSplit) high = tag < split_level_;
      if (high) {
        ++counters_.high_refs;
      } else {
        ++counters_.low_refs;
      }
      if constexpr (kPerLevel) count_level_ref(tag);
      const AccessType type = record.type;
      for (std::uint64_t block = first_block;; ++block) {
        if (type <= AccessType::Misc) {
          ++counters_.fetches;
          bool miss;
          if (high) {
            miss = high_access(block, first_record + i + 1);
            counters_.high_misses += miss;
          } else {
            miss = low_access(block);
            counters_.low_misses += miss;
          }
          if constexpr (kPerLevel) {
            if (miss) count_level_miss(tag);
          }
        } else if (type == AccessType::Invalidate) {
          invalidate(high, block);
        }
        if (block == last_block) break;
      }
    }
  }

  void count_level_ref(Tag tag) {
    if (tag >= level_refs_.size()) {
      level_refs_.resize(tag + 1u, 0);
      level_misses_.resize(tag + 1u, 0);
    }
    ++level_refs_[tag];
  }
  void count_level_miss(Tag tag) { ++level_misses_[tag]; }

  [[noreturn]] void throw_does_not_fit(std::uint64_t record_number) const {
    throw UsageError(fmt::format(
        "{}: record {}: the high-level nodes (levels < {}) touched in animation frame {} do not "
        "fit the high-level cache: more than {} distinct {}-byte blocks, but the {}-byte high "
        "cache (of a {}-byte total, low cache {} bytes) holds {}; give a smaller --split-level "
        "or a larger --high-size",
        context_.source_name, record_number, split_level_, animation_frame_,
        retained_.capacity(), config_.block, config_.high_size, config_.size, config_.low_size,
        retained_.capacity()));
  }

  NodeCacheConfig config_;
  const TraceContext& context_;
  std::uint32_t split_level_;
  unsigned block_shift_ = 0;
  // Direct-mapped low cache, then the direct-mapped high cache or the retain
  // filter (blocks already loaded this frame, found with one compare).
  std::vector<std::uint64_t> table_;
  bool low_direct_ = false;
  bool high_direct_ = false;
  std::uint64_t low_mask_ = 0;
  std::uint64_t high_mask_ = 0;
  std::uint64_t high_offset_ = 0;
  std::uint64_t dummy_slot_ = 0;
  std::optional<NodeCache> low_cache_;   // set-associative low (or single) cache
  std::optional<NodeCache> high_cache_;  // set-associative high cache under `cache`
  RetainedBlocks retained_;
  std::vector<Simulator*> group_;  // feed_group's members (this one first)
  std::uint64_t pending_high_misses_ = 0;  // counted loads of a group's chunk
  std::uint64_t animation_frame_ = 0;
  Counters counters_;
  std::vector<std::uint64_t> level_refs_;
  std::vector<std::uint64_t> level_misses_;
};

template <bool kSplit, bool kRetain, bool kPerLevel>
std::unique_ptr<ConfigSimulator> make_simulator_3(const NodeCacheConfig& config,
                                                  std::uint32_t split_level,
                                                  const TraceContext& context) {
  const bool aligned_din = context.form == formats::RecordForm::Din && config.block >= 4;
  if (aligned_din) {
    return std::make_unique<Simulator<kSplit, kRetain, kPerLevel, true>>(config, split_level,
                                                                          context);
  }
  return std::make_unique<Simulator<kSplit, kRetain, kPerLevel, false>>(config, split_level,
                                                                         context);
}

template <bool kSplit, bool kRetain>
std::unique_ptr<ConfigSimulator> make_simulator_2(const NodeCacheConfig& config,
                                                  std::uint32_t split_level,
                                                  const TraceContext& context, bool per_level) {
  if (per_level) return make_simulator_3<kSplit, kRetain, true>(config, split_level, context);
  return make_simulator_3<kSplit, kRetain, false>(config, split_level, context);
}

std::unique_ptr<ConfigSimulator> make_simulator(const NodeCacheConfig& config,
                                                std::uint32_t split_level,
                                                const TraceContext& context, bool per_level) {
  if (config.scheme == Scheme::Single) {
    return make_simulator_2<false, false>(config, split_level, context, per_level);
  }
  if (config.high_policy == HighPolicy::Retain) {
    return make_simulator_2<true, true>(config, split_level, context, per_level);
  }
  return make_simulator_2<true, false>(config, split_level, context, per_level);
}

}  // namespace

// ---------------------------------------------------------------------------

Sweep::Sweep(std::vector<NodeCacheConfig> configs, TraceContext context, bool per_level,
             bool per_frame)
    : configs_(std::move(configs)),
      context_(std::move(context)),
      per_level_(per_level),
      per_frame_(per_frame) {
  const bool split = has_split(configs_);
  needs_levels_ = split || per_level_;
  if (needs_levels_ && !context_.tags_are_levels) {
    throw_untagged_trace(context_, split ? "the split scheme" : "--per-level");
  }
}

Sweep::~Sweep() = default;

void Sweep::start(const formats::RecordBatch& first_batch) {
  started_ = true;
  plan_ = std::make_unique<SplitLevelPlan>(configs_, context_);
  plan_->begin_frame(first_batch.marker ? &*first_batch.marker : nullptr);
  for (std::size_t i = 0; i < configs_.size(); ++i) {
    simulators_.push_back(make_simulator(configs_[i], plan_->current(i), context_, per_level_));
  }
  open_frames_.assign(simulators_.size(), OpenFrame{});
  frame_rows_.assign(simulators_.size(), {});
  // Parts of about equal cost (a split configuration does about twice the
  // work of a single one), filled greedily, the costliest first.
  const std::size_t part_count =
      std::max<std::size_t>(1, std::min(requested_parts_, simulators_.size()));
  parts_.assign(part_count, Part{});
  std::vector<std::size_t> order(simulators_.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  auto cost = [&](std::size_t i) {
    const NodeCacheConfig& config = configs_[i];
    return (config.scheme == Scheme::Split ? 2u : 1u) * (config.assoc == 1 ? 1u : 4u);
  };
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return cost(a) > cost(b); });
  std::vector<unsigned> load(part_count, 0);
  for (const std::size_t i : order) {
    const std::size_t lightest =
        static_cast<std::size_t>(std::min_element(load.begin(), load.end()) - load.begin());
    parts_[lightest].simulators.push_back(i);
    load[lightest] += cost(i);
  }
  for (Part& part : parts_) {
    std::sort(part.simulators.begin(), part.simulators.end());
    constexpr std::size_t kMaxGroup = 8;  // as Simulator::feed_group_flat
    for (const std::size_t i : part.simulators) {
      const std::string key = simulators_[i]->group_key();
      auto group = std::find_if(part.groups.begin(), part.groups.end(), [&](const auto& members) {
        return !key.empty() && members.size() < kMaxGroup &&
               simulators_[members.front()]->group_key() == key;
      });
      if (group == part.groups.end()) {
        part.groups.push_back({i});
      } else {
        group->push_back(i);
      }
    }
  }
}

void Sweep::feed(const formats::RecordBatch& batch) {
  begin_batch(batch);
  for (std::size_t part = 0; part < parts_.size(); ++part) feed_part(batch, part);
}

void Sweep::set_parts(std::size_t parts) { requested_parts_ = std::max<std::size_t>(1, parts); }

std::size_t Sweep::part_count() const { return parts_.size(); }

void Sweep::begin_batch(const formats::RecordBatch& batch) {
  if (!started_) {
    start(batch);
  } else if (batch.marker) {
    plan_->begin_frame(&*batch.marker);  // throws here, in trace order, for a bad marker
  }
}

namespace {

ResultRow counts_since(const ResultRow& now, const ResultRow& before) {
  ResultRow row = now;
  row.refs -= before.refs;
  row.fetches -= before.fetches;
  row.misses -= before.misses;
  row.high_refs -= before.high_refs;
  row.high_misses -= before.high_misses;
  if (row.high_loads) *row.high_loads -= before.high_loads.value_or(0);
  row.low_refs -= before.low_refs;
  row.low_misses -= before.low_misses;
  return row;
}

}  // namespace

void Sweep::change_frame(std::size_t s, const formats::FrameMarker* marker) {
  OpenFrame& open = open_frames_[s];
  if (per_frame_ && open.open) {
    ResultRow row = counts_since(simulators_[s]->result(), open.at_start);
    row.split_level = open.split_level;
    frame_rows_[s].push_back(FrameRow{open.frame, std::move(row)});
  }
  if (marker == nullptr) {  // records before any marker: animation frame 0, K of the start
    open.frame = 0;
    open.split_level = plan_->first(s);
  } else {
    const NodeCacheConfig& config = configs_[s];
    // As the plan resolved it on the reader's thread, which may be ahead.
    open.frame = marker->frame;
    open.split_level =
        config.scheme == Scheme::Split ? resolve_split_level(config, marker, context_) : 0;
    simulators_[s]->begin_frame(marker->frame, open.split_level);
  }
  open.open = true;
  if (per_frame_) open.at_start = simulators_[s]->result();
}

void Sweep::feed_part(const formats::RecordBatch& batch, std::size_t part_index) {
  Part& part = parts_.at(part_index);
  for (const std::size_t s : part.simulators) {
    if (batch.marker) {
      change_frame(s, &*batch.marker);
    } else if (!open_frames_[s].open) {
      change_frame(s, nullptr);
    }
  }
  const Record* const records = batch.records.data();
  const std::size_t count = batch.records.size();
  // In chunks small enough to stay in the processor's cache while every
  // configuration reads them.
  constexpr std::size_t kChunk = 4096;
  for (std::size_t begin = 0; begin < count; begin += kChunk) {
    const std::size_t chunk = std::min(kChunk, count - begin);
    const std::uint64_t first_record = batch.first_record + begin;
    prepare(records + begin, chunk, first_record, part);
    for (const auto& group : part.groups) {
      if (group.size() > 1) {
        part.group_members.clear();
        for (const std::size_t s : group) part.group_members.push_back(simulators_[s].get());
        if (simulators_[group.front()]->feed_group(part.group_members, records + begin, chunk,
                                                   first_record, part.prepared)) {
          continue;
        }
      }
      for (const std::size_t s : group) {
        simulators_[s]->feed(records + begin, chunk, first_record, part.prepared);
      }
    }
  }
}

void Sweep::prepare(const Record* records, std::size_t count, std::uint64_t first_record,
                    Part& part) const {
  // Din records are 4 bytes at a multiple of 4 as Dinero IV reads them.
  std::uint64_t span_bits = 3;
  if (context_.form != formats::RecordForm::Din) {
    span_bits = 0;
    for (std::size_t i = 0; i < count; ++i) {
      const std::uint64_t address = records[i].address;
      span_bits |= address ^ (address + std::max<std::uint32_t>(records[i].size, 1) - 1);
    }
  }
  unsigned not_demand = 0;
  unsigned not_level = 0;
  for (std::size_t i = 0; i < count; ++i) {
    not_demand |= static_cast<unsigned>(records[i].type > AccessType::Misc);
    not_level |= static_cast<unsigned>(records[i].tag > formats::kMaxLevel);
  }
  bool demand_only = not_demand == 0;
  const bool all_levels = not_level == 0;
  if (!all_levels) {
    // Other streams (counted apart), or untagged records where levels are needed.
    for (std::size_t i = 0; i < count; ++i) {
      const Tag tag = records[i].tag;
      if (formats::is_level(tag)) continue;
      if (is_other_stream(tag)) {
        ++part.other_stream_records;
        demand_only = false;
      } else if (needs_levels_) {
        throw_untagged_record(context_, first_record + i + 1,
                              "the split scheme and --per-level route");
      }
    }
  }
  part.prepared.span_bits = span_bits;
  part.prepared.demand_only = demand_only;
}

TraceResult Sweep::finish() {
  if (!started_) start(formats::RecordBatch{});
  TraceResult result;
  for (std::size_t s = 0; s < simulators_.size(); ++s) {
    ResultRow row = simulators_[s]->result();
    row.split_level = plan_->first(s);
    result.rows.push_back(std::move(row));
    if (per_level_) simulators_[s]->append_level_rows(result.level_rows);
  }
  if (per_frame_) {
    for (std::size_t s = 0; s < simulators_.size(); ++s) {
      if (!open_frames_[s].open) change_frame(s, nullptr);  // a trace without records
      change_frame(s, nullptr);  // closes the last frame
    }
    // Every simulator saw the same frames: frame by frame, configurations in order.
    const std::size_t frames = frame_rows_.empty() ? 0 : frame_rows_[0].size();
    for (std::size_t f = 0; f < frames; ++f) {
      for (const auto& rows : frame_rows_) result.frame_rows.push_back(rows[f]);
    }
  }
  // Every part sees every record; part 0's count is the trace's.
  const std::uint64_t other_stream_records = parts_.empty() ? 0 : parts_[0].other_stream_records;
  result.other_stream_records = other_stream_records;
  result.notes = plan_->notes();
  if (other_stream_records > 0) {
    result.notes.push_back(other_streams_note(context_.trace, other_stream_records));
  }
  return result;
}

}  // namespace nodetrace::cachesim
