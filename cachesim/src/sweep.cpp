// The sweep: configurations split into parts of equal cost, batches routed
// to every part in trace order, K per animation frame, the per-frame rows.
#include "nodetrace/cachesim/sweep.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <map>
#include <set>

#include "config_simulator.hpp"
#include "stack_group.hpp"
#include "nodetrace/formats/error.hpp"

namespace nodetrace::cachesim {

using formats::AccessType;
using formats::Record;
using formats::Tag;

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
  // Units fed by one loop: a stack group (configurations that set stacks
  // answer together, two or more of one key), split configurations of
  // tables only fed together, or one configuration.
  simulators_.resize(configs_.size());
  std::vector<std::vector<std::size_t>> units;
  std::vector<unsigned> unit_cost;
  std::map<std::string, std::vector<std::size_t>> by_key;
  std::vector<std::size_t> alone;
  for (std::size_t i = 0; i < configs_.size(); ++i) {
    const std::string key = stack_group_key(configs_[i]);
    if (key.empty()) {
      alone.push_back(i);
    } else {
      by_key[key].push_back(i);
    }
  }
  for (auto& [key, members] : by_key) {
    if (members.size() == 1) {
      alone.push_back(members.front());
      continue;
    }
    std::vector<NodeCacheConfig> member_configs;
    std::set<std::pair<std::uint64_t, std::uint32_t>> shapes;  // the stacks' set counts, about
    for (const std::size_t i : members) {
      member_configs.push_back(configs_[i]);
      const NodeCacheConfig& config = configs_[i];
      shapes.emplace(config.scheme == Scheme::Split ? config.low_size : config.size, config.assoc);
    }
    auto group = make_stack_group(member_configs, plan_->current(members.front()), context_,
                                  per_level_);
    for (std::size_t m = 0; m < members.size(); ++m) simulators_[members[m]] = std::move(group[m]);
    unit_cost.push_back(static_cast<unsigned>(2 + shapes.size()));
    units.push_back(std::move(members));
  }
  // Split configurations of tables only, of other K: up to kMaxTogether fed
  // by one loop (each record read once).
  std::sort(alone.begin(), alone.end());
  std::map<std::string, std::vector<std::vector<std::size_t>>> together;
  std::vector<std::size_t> by_itself;
  for (const std::size_t i : alone) {
    const std::string key = together_key(configs_[i], per_level_);
    if (key.empty()) {
      by_itself.push_back(i);
      continue;
    }
    auto& groups = together[key];
    if (groups.empty() || groups.back().size() == kMaxTogether) groups.emplace_back();
    groups.back().push_back(i);
  }
  for (auto& [key, groups] : together) {
    for (auto& members : groups) {
      if (members.size() == 1) {
        by_itself.push_back(members.front());
        continue;
      }
      std::vector<NodeCacheConfig> member_configs;
      std::vector<std::uint32_t> split_levels;
      for (const std::size_t i : members) {
        member_configs.push_back(configs_[i]);
        split_levels.push_back(plan_->current(i));
      }
      auto group = make_together(member_configs, split_levels, context_);
      for (std::size_t m = 0; m < members.size(); ++m) simulators_[members[m]] = std::move(group[m]);
      unit_cost.push_back(static_cast<unsigned>(2 * members.size()));
      units.push_back(std::move(members));
    }
  }
  for (const std::size_t i : by_itself) {
    simulators_[i] = make_simulator(configs_[i], plan_->current(i), context_, per_level_);
    const NodeCacheConfig& config = configs_[i];
    // A split configuration does about twice the work of a single one.
    unit_cost.push_back((config.scheme == Scheme::Split ? 2u : 1u) * (config.assoc == 1 ? 1u : 4u));
    units.push_back({i});
  }
  open_frames_.assign(simulators_.size(), OpenFrame{});
  frame_rows_.assign(simulators_.size(), {});
  // Parts of about equal cost, filled greedily, the costliest unit first;
  // each unit is fed by its first member.
  const std::size_t part_count =
      std::max<std::size_t>(1, std::min(requested_parts_, units.size()));
  parts_.assign(part_count, Part{});
  std::vector<std::size_t> order(units.size());
  for (std::size_t u = 0; u < order.size(); ++u) order[u] = u;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return unit_cost[a] != unit_cost[b] ? unit_cost[a] > unit_cost[b] : units[a] < units[b];
  });
  std::vector<unsigned> load(part_count, 0);
  for (const std::size_t u : order) {
    const std::size_t lightest =
        static_cast<std::size_t>(std::min_element(load.begin(), load.end()) - load.begin());
    Part& part = parts_[lightest];
    part.simulators.insert(part.simulators.end(), units[u].begin(), units[u].end());
    part.feeders.push_back(units[u].front());
    load[lightest] += unit_cost[u];
  }
  for (Part& part : parts_) {
    std::sort(part.simulators.begin(), part.simulators.end());
    std::sort(part.feeders.begin(), part.feeders.end());
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
    for (const std::size_t s : part.feeders) {
      simulators_[s]->feed(records + begin, chunk, first_record, part.prepared);
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

std::vector<ResultRow> Sweep::counts() const {
  std::vector<ResultRow> rows;
  rows.reserve(simulators_.size());
  for (std::size_t s = 0; s < simulators_.size(); ++s) {
    rows.push_back(simulators_[s]->result());
    rows.back().split_level = plan_->first(s);
  }
  return rows;
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