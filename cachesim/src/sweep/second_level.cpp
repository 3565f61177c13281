#include "nodetrace/cachesim/sweep/second_level.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <optional>
#include <stdexcept>

#include "models/record_blocks.hpp"
#include "models/retained_blocks.hpp"
#include "nodetrace/base/error.hpp"
#include "nodetrace/cachesim/models/set_associative_cache.hpp"

namespace nodetrace::cachesim {

// One copy of a configuration's first level.
struct SecondLevelSimulator::FirstLevel {
  std::optional<SetAssociativeCache> low;   // the single cache for `single`
  std::optional<SetAssociativeCache> high;  // split, high policy `cache`
  std::optional<RetainedBlocks> retained;   // split, high policy `retain`
};

struct SecondLevelSimulator::PerConfig {
  std::vector<FirstLevel> units;
  std::optional<SetAssociativeCache> l2;
  FirstLevelCounts first;
  SecondLevelCounts second;
};

namespace {

void check_policy(ReplacementPolicy policy, const char* what) {
  if (!dinero_has_policy(policy)) {
    throw base::UsageError(fmt::format("--l2-size: the {} is simulated record by record with lru or fifo, "
                                       "not {}",
                                       what, policy_name(policy)));
  }
  if (policy == ReplacementPolicy::Random) {
    throw base::UsageError(fmt::format("--l2-size: the {} cannot be random: its draws would not be the ones the "
                                       "report's first-level counts come from (lru or fifo)",
                                       what));
  }
}

}  // namespace

SecondLevelSimulator::SecondLevelSimulator(const std::vector<Configuration>& configs, const TraceContext& context,
                                           unsigned units, const CacheGeometry& l2)
    : configs_(configs), context_(context), l2_geometry_(l2), units_(std::max(1u, units)) {
  validate_geometry(l2, "second-level cache (--l2-size, --l2-block, --l2-assoc)");
  check_policy(l2.replacement, "second-level cache");
  per_config_.resize(configs.size());
  for (std::size_t c = 0; c < configs.size(); ++c) {
    const Configuration& config = configs[c];
    check_policy(config.policy, "first level");
    if (config.fetch != FetchPolicy::Demand) {
      throw base::UsageError("--l2-size: the first level must fetch on demand (--fetch demand)");
    }
    PerConfig& per = per_config_[c];
    per.l2.emplace(l2);
    per.second.size = l2.size;
    per.second.block = l2.block_size;
    per.second.assoc = l2.assoc;
    for (unsigned u = 0; u < units_; ++u) {
      FirstLevel& first = per.units.emplace_back();
      if (config.scheme == Scheme::Single) {
        first.low.emplace(CacheGeometry{config.size, config.block, config.assoc, config.policy});
      } else {
        first.low.emplace(CacheGeometry{config.low_size, config.block, config.assoc, config.policy});
        if (config.high_policy == HighPolicy::Retain) {
          first.retained.emplace(config.high_size / config.block);
        } else {
          first.high.emplace(CacheGeometry{config.high_size, config.block, config.high_assoc, config.policy});
        }
      }
    }
  }
}

SecondLevelSimulator::~SecondLevelSimulator() = default;

void SecondLevelSimulator::begin_animation_frame(const formats::AnimationFrameMarker* marker) {
  if (!plan_) plan_ = std::make_unique<SplitLevelPlan>(configs_, context_);
  plan_->begin_animation_frame(marker);
  for (PerConfig& per : per_config_) {
    for (FirstLevel& first : per.units) {
      if (first.retained) first.retained->clear();  // kept for one animation frame
    }
  }
}

void SecondLevelSimulator::feed(const formats::RecordBatch& batch) {
  if (!started_ || batch.marker) begin_animation_frame(batch.marker ? &*batch.marker : nullptr);
  started_ = true;
  if (l2_geometry_.block_size == 1 ||
      std::any_of(configs_.begin(), configs_.end(), [](const Configuration& c) { return c.block == 1; })) {
    refuse_last_block(batch.records.data(), batch.records.size(), context_.form, batch.first_record,
                      context_.source_name);
  }
  for (std::size_t c = 0; c < configs_.size(); ++c) {
    const Configuration& config = configs_[c];
    PerConfig& per = per_config_[c];
    const auto shift = static_cast<unsigned>(std::countr_zero(config.block));
    const auto l2_shift = static_cast<unsigned>(std::countr_zero(l2_geometry_.block_size));
    const bool aligned_din = context_.form == formats::RecordForm::Din && config.block >= 4;
    const bool split = config.scheme == Scheme::Split;
    const std::uint32_t split_level = split ? plan_->current(c) : 0;
    for (const formats::Record& record : batch.records) {
      if (is_other_stream(record.tag) || record.type == formats::AccessType::CopyBack) continue;
      FirstLevel& first = per.units[units_ > 1 ? formats::unit_index(record.unit) : 0];
      const bool high = split && record.tag < split_level;
      const BlockRange blocks = blocks_of(record, context_.form, shift, aligned_din);
      if (record.type == formats::AccessType::Invalidate) {
        // As the sweep's first level: a retained high cache keeps its blocks for the frame.
        if (!high) {
          first.low->invalidate(blocks.first);
        } else if (first.high) {
          first.high->invalidate(blocks.first);
        }
        continue;
      }
      for (std::uint64_t block = blocks.first;; block = blocks.after(block)) {
        bool fetched;
        if (!high) {
          fetched = first.low->access(block);
          per.first.low_misses += fetched;
        } else if (first.retained) {
          fetched = first.retained->insert(block);
          per.first.high_loads += fetched;
        } else {
          fetched = first.high->access(block);
          per.first.high_misses += fetched;
        }
        if (fetched) {
          // One reference of the first-level block; the L2 fetches each of
          // its blocks that the reference spans.
          ++per.second.refs;
          const std::uint64_t address = block << shift;
          const std::uint64_t last = (address + config.block - 1) >> l2_shift;
          for (std::uint64_t l2_block = address >> l2_shift; l2_block <= last; ++l2_block) {
            ++per.second.fetches;
            per.second.misses += per.l2->access(l2_block);
          }
        }
        if (block == blocks.last) break;
      }
    }
  }
}

std::vector<SecondLevelCounts> SecondLevelSimulator::counts() const {
  std::vector<SecondLevelCounts> counts;
  for (const PerConfig& per : per_config_) counts.push_back(per.second);
  return counts;
}

std::vector<FirstLevelCounts> SecondLevelSimulator::first_level_counts() const {
  std::vector<FirstLevelCounts> counts;
  for (const PerConfig& per : per_config_) counts.push_back(per.first);
  return counts;
}

void attach_second_level(std::vector<ResultRow>& rows, const SecondLevelSimulator& simulator) {
  const std::vector<SecondLevelCounts> second = simulator.counts();
  const std::vector<FirstLevelCounts> first = simulator.first_level_counts();
  if (rows.size() != second.size()) throw std::logic_error("second level: one row per configuration expected");
  for (std::size_t c = 0; c < rows.size(); ++c) {
    ResultRow& row = rows[c];
    const bool split = row.config.scheme == Scheme::Split;
    const std::uint64_t low = split ? row.low_misses : row.misses;
    const std::uint64_t high_misses = split && !row.high_loads ? row.high_misses : 0;
    const std::uint64_t loads = row.high_loads.value_or(0);
    if (first[c].low_misses != low || first[c].high_misses != high_misses || first[c].high_loads != loads) {
      throw std::logic_error(fmt::format(
          "second level: its first level of {} {} bytes saw {} low misses, {} high misses, {} loads; the sweep "
          "counted {}, {}, {}",
          scheme_name(row.config.scheme), row.config.size, first[c].low_misses, first[c].high_misses,
          first[c].high_loads, low, high_misses, loads));
    }
    row.l2 = second[c];
  }
}

}  // namespace nodetrace::cachesim
