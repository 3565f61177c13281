// The stack group: a router (single, or split by this frame's K) in front
// of set stacks for the low (or single) caches, set stacks or one retain set
// for the high caches, and every member's counts read from them.
#include "sweep/stack_group.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <optional>

#include "nodetrace/cachesim/models/set_stacks.hpp"
#include "models/record_blocks.hpp"
#include "models/cache_models.hpp"

namespace nodetrace::cachesim {

using formats::AccessType;
using formats::Record;
using formats::Tag;

namespace {

// Deeper stacks would cost more than simulating the caches one by one.
constexpr std::uint32_t kMaxStackWays = 32;

bool stackable(std::uint32_t assoc, ReplacementPolicy policy) {
  // A direct-mapped cache has no choice to make: every policy but opt is LRU.
  return assoc <= kMaxStackWays && misses_as_lru(policy, assoc);
}

unsigned log2_sets(std::uint64_t size, std::uint32_t block, std::uint32_t assoc) {
  return static_cast<unsigned>(std::countr_zero(size / block / assoc));
}

// One set count per distinct number of sets, as deep as its most ways
// (and `entry`, one block deep: see StackPiece).
std::vector<SetStacks::Level> levels_of(const std::vector<std::pair<unsigned, std::uint32_t>>& caches,
                                        std::optional<unsigned> entry = std::nullopt) {
  std::vector<SetStacks::Level> levels;
  if (entry) levels.push_back({*entry, 1});
  for (const auto& [log2, ways] : caches) {
    auto at = std::find_if(levels.begin(), levels.end(),
                           [log2 = log2](const SetStacks::Level& level) { return level.log2_sets == log2; });
    if (at == levels.end()) {
      levels.push_back({log2, ways});
    } else {
      at->depth = std::max(at->depth, ways);
    }
  }
  return levels;
}

class StackGroup {
 public:
  // `retain_bound`: the member of the whole group (all pieces) whose high
  // cache holds the fewest blocks: every piece's retain set has its
  // capacity and its error names it, so pieces fail alike.
  StackGroup(const std::vector<Configuration>& configs, std::uint32_t split_level,
             const TraceContext& context, bool per_level, const Configuration& retain_bound,
             std::optional<unsigned> entry_log2_sets = std::nullopt,
             std::shared_ptr<const GridFilterOutput> grid_filtered = nullptr)
      : context_(context),
        grid_filtered_(std::move(grid_filtered)),
        split_(configs.front().scheme == Scheme::Split),
        retain_(split_ && configs.front().high_policy == HighPolicy::Retain),
        per_level_(per_level),
        aligned_din_(context.form == formats::RecordForm::Din && configs.front().block >= 4),
        shift_(static_cast<unsigned>(std::countr_zero(configs.front().block))),
        split_level_(split_level),
        low_(levels_of(cache_shapes(configs, false), entry_log2_sets), per_level),
        retained_(retain_ ? retain_bound.high_size / retain_bound.block : 0),
        retain_bound_(retain_bound) {
    for (const Configuration& config : configs) {
      Member member;
      member.config = config;
      const std::uint64_t low_size = split_ ? config.low_size : config.size;
      member.low_log2_sets = log2_sets(low_size, config.block, config.assoc);
      if (split_ && !retain_) {
        member.high_log2_sets = log2_sets(config.high_size, config.block, config.high_assoc);
      }
      members_.push_back(std::move(member));
    }
    if (split_ && !retain_) high_.emplace(levels_of(cache_shapes(configs, true)), per_level);
  }

  // Estimating only: the stacks walk the demand fetches of nodes among
  // `records` (one block each; a retained high cache is not simulated).
  void probe(const Record* records, std::size_t count) {
    const Tag split_level = static_cast<Tag>(std::min<std::uint32_t>(split_level_, 0xFFFF));
    for (std::size_t i = 0; i < count; ++i) {
      const Record& record = records[i];
      if (record.type > AccessType::Misc || !formats::is_level(record.tag)) continue;
      const std::uint64_t block = record.address >> shift_;
      if (split_ && record.tag < split_level) {
        ++high_refs_;
        if (!retain_) high_->access(block);
      } else {
        low_.access(block);
      }
    }
  }
  const SetStacks& low_stacks() const { return low_; }
  const SetStacks* high_stacks() const { return high_ ? &*high_ : nullptr; }
  std::uint64_t high_refs() const { return high_refs_; }
  unsigned low_log2_sets(std::size_t m) const { return members_[m].low_log2_sets; }
  unsigned high_log2_sets(std::size_t m) const { return members_[m].high_log2_sets; }
  bool split() const { return split_; }
  bool retain() const { return retain_; }

  void begin_animation_frame(std::uint64_t animation_frame, std::uint32_t split_level) {
    animation_frame_ = animation_frame;
    split_level_ = split_level;
    if (retain_) retained_.begin_animation_frame();
  }

  void feed(const Record* records, std::size_t count, std::uint64_t first_record,
            const PreparedBatch& prepared) {
    if (!handed_over_ && prepared.demand_only &&
        prepared.span_bits < members_.front().config.block) {
      if (!split_) {
        per_level_ ? feed_blocks<false, false, true>(records, count, first_record)
                   : feed_blocks<false, false, false>(records, count, first_record);
      } else if (retain_) {
        per_level_ ? feed_blocks<true, true, true>(records, count, first_record)
                   : feed_blocks<true, true, false>(records, count, first_record);
      } else {
        per_level_ ? feed_blocks<true, false, true>(records, count, first_record)
                   : feed_blocks<true, false, false>(records, count, first_record);
      }
      return;
    }
    if (!handed_over_) {
      const bool invalidates = std::any_of(records, records + count, [](const Record& record) {
        return record.type == AccessType::Invalidate;
      });
      if (invalidates) hand_over();
    }
    feed_generic(records, count, first_record);
  }

  ResultRow result(std::size_t m) const {
    const Member& member = members_[m];
    ResultRow row;
    row.trace = context_.trace;
    row.config = member.config;
    row.refs = refs_;
    row.fetches = fetches_;
    const std::uint64_t low_misses =
        low_.misses(member.low_log2_sets, member.config.assoc) + member.low_misses_after;
    if (!split_) {
      row.misses = low_misses;
      return row;
    }
    row.split_level = split_level_;
    row.high_refs = high_refs_;
    row.low_refs = refs_ - high_refs_;
    row.low_misses = low_misses;
    if (retain_) {
      row.high_loads = loads_;
      row.high_misses = member.config.count_loads ? loads_ : 0;
    } else {
      row.high_misses = high_->misses(member.high_log2_sets, member.config.high_assoc) +
                        member.high_misses_after;
    }
    row.misses = row.high_misses + row.low_misses;
    return row;
  }

  void append_level_rows(std::size_t m, std::vector<LevelRow>& rows) const {
    const Member& member = members_[m];
    for (std::size_t tag = 0; tag < refs_by_tag_.size(); ++tag) {
      if (refs_by_tag_[tag] == 0) continue;
      const auto level = static_cast<unsigned>(tag);
      std::uint64_t misses = low_.misses(member.low_log2_sets, member.config.assoc, level);
      if (tag < member.misses_by_tag_after.size()) misses += member.misses_by_tag_after[tag];
      if (retain_) {
        if (member.config.count_loads && tag < loads_by_tag_.size()) misses += loads_by_tag_[tag];
      } else if (split_) {
        misses += high_->misses(member.high_log2_sets, member.config.high_assoc, level);
      }
      rows.push_back(LevelRow{context_.trace, member.config, 0, level,
                              refs_by_tag_[tag], misses});
    }
  }

 private:
  struct Member {
    Configuration config;
    unsigned low_log2_sets = 0;
    unsigned high_log2_sets = 0;
    // After a hand-over (an invalidate): the member's own caches, filled
    // from the stacks, and the misses they count from then on.
    std::optional<SetAssociativeCache> low_cache;
    std::optional<SetAssociativeCache> high_cache;
    std::uint64_t low_misses_after = 0;
    std::uint64_t high_misses_after = 0;
    std::vector<std::uint64_t> misses_by_tag_after;
  };

  static std::vector<std::pair<unsigned, std::uint32_t>> cache_shapes(
      const std::vector<Configuration>& configs, bool high) {
    std::vector<std::pair<unsigned, std::uint32_t>> shapes;
    for (const Configuration& config : configs) {
      if (high) {
        shapes.emplace_back(log2_sets(config.high_size, config.block, config.high_assoc),
                            config.high_assoc);
      } else {
        const std::uint64_t size = config.scheme == Scheme::Split ? config.low_size : config.size;
        shapes.emplace_back(log2_sets(size, config.block, config.assoc), config.assoc);
      }
    }
    return shapes;
  }

  // Every record one demand fetch of one block (din addresses need no
  // rounding: blocks are at least 4 bytes).
  template <bool kSplit, bool kRetain, bool kByTag>
  void feed_blocks(const Record* records, std::size_t count, std::uint64_t first_record) {
    const unsigned shift = shift_;
    const Tag split_level = static_cast<Tag>(std::min<std::uint32_t>(split_level_, 0xFFFF));
    std::uint64_t high_refs = 0;
    if constexpr (!kByTag) {
      // Each side's blocks in order, then its stacks run over them set
      // count by set count (the two sides' stacks are independent).
      if constexpr (!kSplit) {
        const GridFilterOutput* const grid = grid_filtered_.get();
        if (grid != nullptr && grid->records == records && grid->count == count) {
          low_.access_records_filtered(records, count, shift, grid->lists, grid->blocks_fit_32_bits);
        } else {
          low_.access_records(records, count, shift);
        }
        refs_ += count;
        fetches_ += count;
        return;
      }
      low_blocks_.clear();
      high_blocks_.clear();
      for (std::size_t i = 0; i < count; ++i) {
        const std::uint64_t block = records[i].address >> shift;
        if (kSplit && records[i].tag < split_level) {
          ++high_refs;
          if constexpr (kRetain) {
            retain_access(block, records[i].tag, first_record + i + 1);
          } else {
            high_blocks_.push_back(block);
          }
        } else {
          low_blocks_.push_back(block);
        }
      }
      low_.access_blocks(low_blocks_.data(), low_blocks_.size());
      if (kSplit && !kRetain) high_->access_blocks(high_blocks_.data(), high_blocks_.size());
      refs_ += count;
      fetches_ += count;
      high_refs_ += high_refs;
      return;
    }
    for (std::size_t i = 0; i < count; ++i) {
      const std::uint64_t block = records[i].address >> shift;
      const Tag tag = records[i].tag;
      if constexpr (kByTag) count_ref(tag);
      if (kSplit && tag < split_level) {
        ++high_refs;
        if constexpr (kRetain) {
          retain_access(block, tag, first_record + i + 1);
        } else {
          high_->access(block, tag);
        }
      } else {
        low_.access(block, tag);
      }
    }
    refs_ += count;
    fetches_ += count;
    high_refs_ += high_refs;
  }

  void count_ref(Tag tag) {
    if (tag >= refs_by_tag_.size()) refs_by_tag_.resize(tag + 1u, 0);
    ++refs_by_tag_[tag];
  }

  void retain_access(std::uint64_t block, Tag tag, std::uint64_t record_number) {
    if (!retained_.access(block)) return;
    ++loads_;
    if (per_level_) {
      if (tag >= loads_by_tag_.size()) loads_by_tag_.resize(tag + 1u, 0);
      ++loads_by_tag_[tag];
    }
    if (retained_.count() > retained_.capacity()) {
      throw_high_levels_do_not_fit(context_, retain_bound_, record_number,
                                   split_level_, animation_frame_, retained_.capacity());
    }
  }

  // From here on each member simulates its own caches, starting from what
  // the stacks hold.
  void hand_over() {
    handed_over_ = true;
    for (Member& member : members_) {
      const Configuration& config = member.config;
      const std::uint64_t low_size = split_ ? config.low_size : config.size;
      // Stacked caches miss as LRU does (stackable()): LRU takes over from the stacks.
      member.low_cache.emplace(CacheGeometry{low_size, config.block, config.assoc, ReplacementPolicy::Lru});
      for (std::uint64_t set = 0; set < member.low_cache->sets(); ++set) {
        member.low_cache->assign_set(set, low_.ways_of(member.low_log2_sets, set, config.assoc));
      }
      if (split_ && !retain_) {
        member.high_cache.emplace(
            CacheGeometry{config.high_size, config.block, config.high_assoc, ReplacementPolicy::Lru});
        for (std::uint64_t set = 0; set < member.high_cache->sets(); ++set) {
          member.high_cache->assign_set(
              set, high_->ways_of(member.high_log2_sets, set, config.high_assoc));
        }
      }
    }
  }

  // Any record: types, spans, other streams; the stacks until a hand-over,
  // the members' own caches after it.
  void feed_generic(const Record* records, std::size_t count, std::uint64_t first_record) {
    for (std::size_t i = 0; i < count; ++i) {
      const Record& record = records[i];
      const Tag tag = record.tag;
      if (is_other_stream(tag)) continue;
      const BlockRange blocks = blocks_of(record, context_.form, shift_, aligned_din_);
      ++refs_;
      const bool high = split_ && tag < split_level_;
      high_refs_ += high;
      if (per_level_) count_ref(tag);
      const AccessType type = record.type;
      for (std::uint64_t block = blocks.first;; block = blocks.after(block)) {
        if (type <= AccessType::Misc) {
          ++fetches_;
          fetch(high, block, tag, first_record + i + 1);
        } else if (type == AccessType::Invalidate) {
          invalidate(high, block);
        }
        if (block == blocks.last) break;
      }
    }
  }

  void fetch(bool high, std::uint64_t block, Tag tag, std::uint64_t record_number) {
    if (high && retain_) {
      retain_access(block, tag, record_number);
    } else if (!handed_over_) {
      (high ? *high_ : low_).access(block, tag);
    } else {
      for (Member& member : members_) {
        const bool miss = high ? member.high_cache->access(block) : member.low_cache->access(block);
        (high ? member.high_misses_after : member.low_misses_after) += miss;
        if (miss && per_level_) {
          if (tag >= member.misses_by_tag_after.size()) {
            member.misses_by_tag_after.resize(tag + 1u, 0);
          }
          ++member.misses_by_tag_after[tag];
        }
      }
    }
  }

  // Only after a hand-over (feed hands over before a chunk with invalidates);
  // a retained high cache keeps its blocks for the frame.
  void invalidate(bool high, std::uint64_t block) {
    if (high && retain_) return;
    for (Member& member : members_) {
      (high ? member.high_cache : member.low_cache)->invalidate(block);
    }
  }

  const TraceContext& context_;
  // The policy grid fed each chunk just before, on this thread (or null).
  std::shared_ptr<const GridFilterOutput> grid_filtered_;
  bool split_;
  bool retain_;
  bool per_level_;
  bool aligned_din_;
  unsigned shift_;
  std::uint32_t split_level_;
  std::uint64_t animation_frame_ = 0;
  SetStacks low_;                // the single caches, or the split scheme's low caches
  std::optional<SetStacks> high_;  // split under `cache`
  RetainSet retained_;             // split under `retain`: the retain bound's capacity
  Configuration retain_bound_;
  std::uint64_t loads_ = 0;
  std::vector<std::uint64_t> loads_by_tag_;
  std::uint64_t refs_ = 0;
  std::uint64_t fetches_ = 0;
  std::uint64_t high_refs_ = 0;
  std::vector<std::uint64_t> refs_by_tag_;
  bool handed_over_ = false;
  std::vector<Member> members_;
  std::vector<std::uint64_t> low_blocks_;   // feed_blocks' scratch
  std::vector<std::uint64_t> high_blocks_;  // feed_blocks' scratch
};

class StackMember final : public ConfigSimulator {
 public:
  StackMember(std::shared_ptr<StackGroup> group, std::size_t index)
      : group_(std::move(group)), index_(index) {}

  void begin_animation_frame(std::uint64_t animation_frame, std::uint32_t split_level) override {
    if (index_ == 0) group_->begin_animation_frame(animation_frame, split_level);
  }
  void feed(const Record* records, std::size_t count, std::uint64_t first_record,
            const PreparedBatch& prepared) override {
    if (index_ == 0) group_->feed(records, count, first_record, prepared);
  }
  ResultRow result() const override { return group_->result(index_); }
  void append_level_rows(std::vector<LevelRow>& rows) const override {
    group_->append_level_rows(index_, rows);
  }

 private:
  std::shared_ptr<StackGroup> group_;
  std::size_t index_;
};

}  // namespace

std::string stack_group_key(const Configuration& config) {
  // Stacks answer demand fetches only: a prefetching cache is simulated alone.
  if (config.fetch != FetchPolicy::Demand || config.prefetch.kind != TreeletPrefetch::None ||
      !stackable(config.assoc, config.policy)) {
    return {};
  }
  if (config.scheme == Scheme::Single) return fmt::format("single/{}", config.block);
  if (config.high_policy == HighPolicy::Cache && !stackable(config.high_assoc, config.policy)) {
    return {};
  }
  // Members share K in every animation frame: the same given K, or auto
  // for the same high-cache size.
  const std::string k_rule = config.split_level ? std::to_string(*config.split_level)
                                                : fmt::format("auto{}", config.high_size);
  return fmt::format("split/{}/{}/{}", config.block, high_policy_name(config.high_policy), k_rule);
}

std::size_t tightest_member(const std::vector<Configuration>& members) {
  std::size_t tightest = 0;
  for (std::size_t m = 1; m < members.size(); ++m) {
    if (members[m].high_size / members[m].block <
        members[tightest].high_size / members[tightest].block) {
      tightest = m;
    }
  }
  return tightest;
}

std::vector<std::unique_ptr<ConfigSimulator>> make_stack_group(
    const std::vector<Configuration>& members, std::uint32_t split_level,
    const TraceContext& context, bool per_level, const Configuration* retain_bound,
    std::optional<unsigned> entry_log2_sets, std::shared_ptr<const GridFilterOutput> grid_filtered) {
  const Configuration& bound = retain_bound ? *retain_bound : members[tightest_member(members)];
  auto group = std::make_shared<StackGroup>(members, split_level, context, per_level, bound, entry_log2_sets,
                                            std::move(grid_filtered));
  std::vector<std::unique_ptr<ConfigSimulator>> simulators;
  for (std::size_t m = 0; m < members.size(); ++m) {
    simulators.push_back(std::make_unique<StackMember>(group, m));
  }
  return simulators;
}

void probe_stack_group(const std::vector<Configuration>& members, std::uint32_t split_level,
                       const TraceContext& context, const formats::Record* sample, std::size_t count,
                       const std::function<void(const StackGroupProbe&)>& look) {
  StackGroup group(members, split_level, context, false, members[tightest_member(members)]);
  group.probe(sample, count);
  StackGroupProbe probe;
  probe.split = group.split();
  probe.retain = group.retain();
  probe.high_refs = group.high_refs();
  for (std::size_t m = 0; m < members.size(); ++m) {
    probe.member_low.push_back(group.low_log2_sets(m));
    probe.member_high.push_back(group.high_log2_sets(m));
  }
  probe.low = &group.low_stacks();
  probe.high = group.high_stacks();
  look(probe);
}

}  // namespace nodetrace::cachesim
