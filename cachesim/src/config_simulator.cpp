// The per-configuration simulators: a router (single, or split by level K)
// in front of cache models (direct-mapped tables, set-associative NodeCache,
// the retain set), with fast loops for the common chunk shapes.
#include "config_simulator.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <optional>

#include "nodetrace/formats/error.hpp"
#include "record_blocks.hpp"
#include "retained_blocks.hpp"

namespace nodetrace::cachesim {

using formats::AccessType;
using formats::Record;
using formats::Tag;
using formats::UsageError;

namespace {


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
    table_.assign(low_sets + high_sets, NodeCache::kInvalid);
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
      const BlockRange blocks = blocks_of(record, context_.form, shift, kAlignedDin);
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
      for (std::uint64_t block = blocks.first;; ++block) {
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
        if (block == blocks.last) break;
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
    throw_high_levels_do_not_fit(context_, config_, record_number, split_level_, animation_frame_,
                                 retained_.capacity());
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
  std::optional<NodeCache> low_cache_;   // set-associative low (or single) cache
  std::optional<NodeCache> high_cache_;  // set-associative high cache under `cache`
  RetainedBlocks retained_;
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

}  // namespace

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

}  // namespace nodetrace::cachesim
