// The sweep: configurations split into parts of about equal estimated cost
// (a stack group cut into pieces where it alone is more than a part's
// share), batches routed to every part in trace order, K per animation
// frame, the per-frame rows.
#include "nodetrace/cachesim/sweep/sweep.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <ctime>
#include <map>
#include <optional>

#include "models/record_blocks.hpp"
#include "nodetrace/base/error.hpp"
#include "nodetrace/cachesim/dinero/address_width.hpp"
#include "sweep/config_simulator.hpp"
#include "sweep/policy_grid.hpp"
#include "sweep/stack_group.hpp"
#include "nodetrace/base/error.hpp"

namespace nodetrace::cachesim {

using formats::AccessType;
using formats::Record;
using formats::Tag;

Sweep::Sweep(std::vector<Configuration> configs, TraceContext context, bool per_level,
             bool per_animation_frame)
    : configs_(std::move(configs)),
      context_(std::move(context)),
      per_level_(per_level),
      per_animation_frame_(per_animation_frame) {
  const bool split = has_split(configs_);
  needs_levels_ = split || per_level_;
  if (needs_levels_ && !context_.tags_are_levels) {
    throw_untagged_trace(context_, split ? "the split scheme" : "--per-level");
  }
  one_byte_blocks_ = std::any_of(configs_.begin(), configs_.end(),
                                 [](const Configuration& config) { return config.block == 1; });
  prefetching_ = std::any_of(configs_.begin(), configs_.end(),
                             [](const Configuration& config) { return config.fetch != FetchPolicy::Demand; });
  reported_ = configs_.size();
  treelet_prefetch_ = has_treelet_prefetch(configs_);
  if (treelet_prefetch_) {
    // Coverage compares each configuration's misses with its own without
    // the prefetcher: simulated alongside, unless it is reported anyway.
    for (std::size_t c = 0; c < reported_; ++c) {
      Configuration without = configs_[c];
      without.prefetch = PrefetchSpec{};
      const auto found = std::find(configs_.begin(), configs_.end(), without);
      without_prefetch_.push_back(static_cast<std::size_t>(found - configs_.begin()));
      if (found == configs_.end()) configs_.push_back(without);
    }
  }
}

Sweep::~Sweep() = default;

namespace {

// Records of the first batch that probe a stack group's cost (parts > 1).
constexpr std::size_t kProbeRecords = std::size_t{1} << 17;

// Estimated work per record of one configuration simulated by itself, in
// the units of StackGroupCost (a set count looked at is about 1): a rough
// weight of its cache's access, the split scheme's two caches and router
// costing about half as much again (measured on the Table 1 grid: three
// direct-mapped split configurations fed together took 1.8 times the CPU
// of the stack group of the three single ones).
double cost_alone(const Configuration& config) {
  const double cache = config.assoc == 1 ? 1.0 : 1.0 + 0.5 * config.assoc;
  return 1.0 + (config.scheme == Scheme::Split ? 1.5 : 1.0) * cache;
}

// Estimated work per record of one member of a policy grid, in the units
// of StackGroupCost: its filters leave it 17 to 60 % of the fetches
// (measured on BART Kitchen, 8-byte blocks, 512 down to 64 sets), each
// costing about twice a set-associative access (a miss ratio of 20-30 %
// among them mispredicts).
constexpr double kGridMemberCost = 1.0;

// The calling thread's CPU time: what a unit's feed costs, whatever else
// runs on the machine.
double thread_cpu_seconds() {
  timespec now{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
  return static_cast<double>(now.tv_sec) + static_cast<double>(now.tv_nsec) * 1e-9;
}

}  // namespace

void Sweep::start(const formats::RecordBatch& first_batch) {
  started_ = true;
  // A trace that carries treelet maps carries one with every animation
  // frame's marker, its first batch's included.
  if (treelet_prefetch_ && !(first_batch.marker && first_batch.marker->treelets)) {
    throw base::UsageError(fmt::format(
        "--prefetch treelet: {} carries no treelet map (its first animation frame's marker has none); traces "
        "rendered with `tracer render --layout treelet` carry one",
        context_.source_name));
  }
  plan_ = std::make_unique<SplitLevelPlan>(configs_, context_);
  plan_->begin_animation_frame(first_batch.marker ? &*first_batch.marker : nullptr);
  // Units fed by one loop: a stack group (configurations that set stacks
  // answer together, two or more of one key) or a piece of one, a policy
  // grid, split configurations of tables only fed together, or one
  // configuration.
  simulators_.resize(configs_.size());
  std::vector<std::vector<std::size_t>> units;
  std::vector<double> unit_cost;
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
  // With one part nothing is balanced: no probe, every group whole.
  const bool balance = requested_parts_ > 1;
  struct Group {
    std::string key;
    std::vector<std::size_t> members;
    std::vector<Configuration> configs;
    std::optional<StackGroupCost> cost;
  };
  std::vector<Group> groups;
  for (auto& [key, members] : by_key) {
    if (members.size() == 1) {
      alone.push_back(members.front());
      continue;
    }
    Group group;
    group.key = key;
    for (const std::size_t i : members) group.configs.push_back(configs_[i]);
    if (balance) {
      group.cost.emplace(group.configs, plan_->current(members.front()), context_, per_level_,
                         first_batch.records.data(),
                         std::min(first_batch.records.size(), kProbeRecords));
    }
    group.members = std::move(members);
    groups.push_back(std::move(group));
  }
  // Single caches under the policies of a policy grid, one grid per block
  // size (one configuration too: its packed cache and repeat filter are
  // faster than a policy cache).
  std::sort(alone.begin(), alone.end());
  std::map<std::string, std::vector<std::size_t>> policy_grids;
  std::vector<std::size_t> not_in_grid;
  for (const std::size_t i : alone) {
    const std::string key = policy_grid_key(configs_[i], per_level_);
    if (key.empty()) {
      not_in_grid.push_back(i);
    } else {
      policy_grids[key].push_back(i);
    }
  }
  // A grid's unit, which the stack group of its key joins.
  std::map<std::string, std::pair<std::size_t, std::shared_ptr<const GridFilterOutput>>> grid_units;
  for (auto& [key, members] : policy_grids) {
    std::vector<Configuration> member_configs;
    double cost = 1.0;
    for (const std::size_t i : members) {
      member_configs.push_back(configs_[i]);
      cost += kGridMemberCost;
    }
    PolicyGridSimulators made = make_policy_grid(member_configs, context_);
    for (std::size_t m = 0; m < members.size(); ++m) simulators_[members[m]] = std::move(made.members[m]);
    grid_units[key] = {units.size(), std::move(made.filtered)};
    unit_cost.push_back(cost);
    units.push_back(std::move(members));
  }
  // Split configurations of tables only, of other K: up to kMaxTogether fed
  // by one loop (each record read once).
  std::map<std::string, std::vector<std::vector<std::size_t>>> together;
  std::vector<std::size_t> by_itself;
  for (const std::size_t i : not_in_grid) {
    const std::string key = together_key(configs_[i], per_level_);
    if (key.empty()) {
      by_itself.push_back(i);
      continue;
    }
    auto& sets = together[key];
    if (sets.empty() || sets.back().size() == kMaxTogether) sets.emplace_back();
    sets.back().push_back(i);
  }
  for (auto& [key, sets] : together) {
    for (auto& members : sets) {
      if (members.size() == 1) {
        by_itself.push_back(members.front());
        continue;
      }
      std::vector<Configuration> member_configs;
      std::vector<std::uint32_t> split_levels;
      double cost = 1.0;
      for (const std::size_t i : members) {
        member_configs.push_back(configs_[i]);
        split_levels.push_back(plan_->current(i));
        cost += cost_alone(configs_[i]) - 1.0;  // one router for all
      }
      auto made = make_together(member_configs, split_levels, context_);
      for (std::size_t m = 0; m < members.size(); ++m) simulators_[members[m]] = std::move(made[m]);
      unit_cost.push_back(cost);
      units.push_back(std::move(members));
    }
  }
  OptStreams opt_streams;  // held by the simulators that share them
  for (const std::size_t i : by_itself) {
    simulators_[i] = make_simulator(configs_[i], plan_->current(i), context_, per_level_, &opt_streams);
    unit_cost.push_back(cost_alone(configs_[i]));
    units.push_back({i});
  }
  // A stack group that alone is more than a part's share is cut into
  // pieces (as many as it needs, at most one per part).
  double total = 0;
  for (const double cost : unit_cost) total += cost;
  for (const Group& group : groups) total += group.cost ? group.cost->cut(1).front().cost : 0;
  const double share = total / static_cast<double>(requested_parts_);
  std::vector<std::vector<std::size_t>> leaders(units.size());
  for (std::size_t u = 0; u < units.size(); ++u) leaders[u] = {units[u].front()};
  for (Group& group : groups) {
    // The stack group of a policy grid's block size walks the lists the
    // grid's filters kept, right after the grid on the same thread, so it
    // joins the grid's unit whole (the grid of 4 policies x 3 sizes x 3
    // ways on BART Kitchen: 3.05 s of CPU against 3.20 s with the group on
    // a thread of its own, medians of 15 runs in turn).
    if (const auto grid = grid_units.find(group.key); grid != grid_units.end()) {
      const auto [unit, filtered] = grid->second;
      auto made = make_stack_group(group.configs, plan_->current(group.members.front()), context_, per_level_,
                                   nullptr, std::nullopt, filtered);
      for (std::size_t m = 0; m < group.members.size(); ++m) simulators_[group.members[m]] = std::move(made[m]);
      unit_cost[unit] += group.cost ? group.cost->cut(1).front().cost : 0;
      leaders[unit].push_back(group.members.front());
      units[unit].insert(units[unit].end(), group.members.begin(), group.members.end());
      std::sort(units[unit].begin(), units[unit].end());
      continue;
    }
    std::vector<StackPiece> pieces;
    if (group.cost) {
      const double whole = group.cost->cut(1).front().cost;
      // Twice the parts it needs, so that measured times can even out an
      // estimate that was wrong (the first batch need not be typical);
      // but a group alone in the sweep only as many: every piece past the
      // first reads every record again to enter (measured: a tenth of the
      // CPU of 36 LRU configurations on BART Kitchen, whose two pieces the
      // estimate balanced to 3 % of the threads' time).
      const auto wanted = std::max<std::size_t>(1, static_cast<std::size_t>(std::ceil(whole / share - 1e-9)));
      const bool alone = groups.size() == 1 && unit_cost.empty();
      pieces = group.cost->cut(std::min(group.cost->max_pieces(),
                                        wanted > 1 && !alone ? std::size_t{2} * wanted : wanted));
    } else {
      StackPiece whole;
      for (std::size_t m = 0; m < group.members.size(); ++m) whole.members.push_back(m);
      pieces.push_back(std::move(whole));
    }
    // Every piece's retain set bounded by the whole group's tightest member.
    const Configuration bound = group.configs[tightest_member(group.configs)];
    for (const StackPiece& piece : pieces) {
      std::vector<Configuration> piece_configs;
      std::vector<std::size_t> members;
      for (const std::size_t m : piece.members) {
        piece_configs.push_back(group.configs[m]);
        members.push_back(group.members[m]);
      }
      auto made = make_stack_group(piece_configs, plan_->current(members.front()), context_,
                                   per_level_, &bound, piece.entry_log2_sets);
      for (std::size_t m = 0; m < members.size(); ++m) simulators_[members[m]] = std::move(made[m]);
      unit_cost.push_back(piece.cost);
      leaders.push_back({members.front()});
      units.push_back(std::move(members));
    }
  }
  open_frames_.assign(simulators_.size(), OpenAnimationFrame{});
  animation_frame_rows_.assign(simulators_.size(), {});
  for (std::size_t u = 0; u < units.size(); ++u) {
    units_.push_back(WorkUnit{std::move(units[u]), std::move(leaders[u]), unit_cost[u], 0.0});
  }
  parts_.assign(std::max<std::size_t>(1, std::min(requested_parts_, units_.size())), Part{});
  assign_parts(unit_cost);
}

void Sweep::assign_parts(const std::vector<double>& cost) {
  std::vector<std::size_t> order(units_.size());
  for (std::size_t u = 0; u < order.size(); ++u) order[u] = u;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return cost[a] > cost[b];
  });
  for (Part& part : parts_) {
    part.units.clear();
    part.simulators.clear();
  }
  std::vector<double> load(parts_.size(), 0);
  for (const std::size_t u : order) {
    const std::size_t lightest =
        static_cast<std::size_t>(std::min_element(load.begin(), load.end()) - load.begin());
    Part& part = parts_[lightest];
    part.units.push_back(u);
    part.simulators.insert(part.simulators.end(), units_[u].simulators.begin(),
                           units_[u].simulators.end());
    load[lightest] += cost[u];
  }
  for (Part& part : parts_) {
    // Fed in report order (an error names the first configuration in it).
    std::sort(part.units.begin(), part.units.end(), [&](std::size_t a, std::size_t b) {
      return units_[a].simulators.front() < units_[b].simulators.front();
    });
    std::sort(part.simulators.begin(), part.simulators.end());
  }
}

void Sweep::feed(const formats::RecordBatch& batch) {
  begin_batch(batch);
  for (std::size_t part = 0; part < parts_.size(); ++part) feed_part(batch, part);
}

void Sweep::set_parts(std::size_t parts) { requested_parts_ = std::max<std::size_t>(1, parts); }

std::size_t Sweep::part_count() const { return parts_.size(); }

void Sweep::begin_batch(const formats::RecordBatch& batch) {
  if (one_byte_blocks_) {
    refuse_last_block(batch.records.data(), batch.records.size(), context_.form, batch.first_record,
                      context_.source_name);
  }
  if (prefetching_) {
    // Dinero IV's engine, which simulates the prefetching fetch policies,
    // keeps 32-bit addresses, where cachesim run's other paths keep 64.
    for (std::size_t i = 0; i < batch.records.size(); ++i) {
      if (is_other_stream(batch.records[i].tag) ||
          records_beyond_32_bits({&batch.records[i], 1}, context_.form) == 0) {
        continue;
      }
      throw base::FormatError(fmt::format(
          "{}: record {}: address 0x{:x} reaches 2^32: a --fetch other than demand is simulated by Dinero IV's "
          "engine, which keeps 32-bit addresses (cachesim dinero); cachesim run keeps 64, so it is not "
          "simulated: give --fetch demand",
          context_.source_name, batch.first_record + i + 1, batch.records[i].address));
    }
  }
  if (treelet_prefetch_ && batch.marker && batch.marker->treelets) {
    check_treelet_map(*batch.marker->treelets, batch.marker->frame, context_.source_name);
  }
  if (!started_) {
    start(batch);
  } else if (batch.marker) {
    plan_->begin_animation_frame(&*batch.marker);  // throws here, in trace order, for a bad marker
  }
  ++batches_;
  // The estimates only start the work off: the CPU time each unit took
  // shares it out from then on, seldom (a unit that moves leaves its
  // stacks in the other core's cache).
  if (parts_.size() > 1 && batches_ >= 4 && std::has_single_bit(batches_)) {
    std::vector<double> seconds;
    for (const WorkUnit& unit : units_) seconds.push_back(unit.seconds);
    assign_parts(seconds);
  }
}

namespace {

// The blocks a row's caches fetched from memory on demand: its misses, a
// retained high cache's loads whether they count as misses or not.
std::uint64_t demand_blocks_fetched(const ResultRow& row) {
  if (row.config.scheme == Scheme::Single) return row.misses;
  return row.low_misses + (row.config.high_policy == HighPolicy::Retain ? row.high_loads.value_or(0) : row.high_misses);
}

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

void Sweep::change_frame(std::size_t s, const formats::AnimationFrameMarker* marker) {
  OpenAnimationFrame& open = open_frames_[s];
  if (per_animation_frame_ && open.open) {
    ResultRow row = counts_since(simulators_[s]->result(), open.at_start);
    row.split_level = open.split_level;
    animation_frame_rows_[s].push_back(AnimationFrameRow{open.frame, std::move(row)});
  }
  if (marker == nullptr) {  // records before any marker: animation frame 0, K of the start
    open.frame = 0;
    open.split_level = plan_->first(s);
  } else {
    const Configuration& config = configs_[s];
    // As the plan resolved it on the reader's thread, which may be ahead.
    open.frame = marker->frame;
    open.split_level =
        config.scheme == Scheme::Split ? simulated_split_level(config, marker, context_) : 0;
    simulators_[s]->begin_animation_frame(marker->frame, open.split_level);
    simulators_[s]->begin_treelets(marker->treelets ? &*marker->treelets : nullptr);
  }
  open.open = true;
  if (per_animation_frame_) open.at_start = simulators_[s]->result();
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
  // configuration reads them; with parts, every kTimedEvery-th chunk's
  // feeds are timed (reading the clock is a system call).
  constexpr std::size_t kChunk = 4096;
  constexpr std::size_t kTimedEvery = 8;
  for (std::size_t begin = 0; begin < count; begin += kChunk) {
    const std::size_t chunk = std::min(kChunk, count - begin);
    const std::uint64_t first_record = batch.first_record + begin;
    prepare(records + begin, chunk, first_record, batch.kinds, part);
    const bool timed = parts_.size() > 1 && (first_record / kChunk) % kTimedEvery == 0;
    double started = timed ? thread_cpu_seconds() : 0;
    for (const std::size_t u : part.units) {
      for (const std::size_t leader : units_[u].leaders) {
        simulators_[leader]->feed(records + begin, chunk, first_record, part.prepared);
      }
      if (timed) {
        const double now = thread_cpu_seconds();
        units_[u].seconds += now - started;
        started = now;
      }
    }
  }
}

void Sweep::prepare(const Record* records, std::size_t count, std::uint64_t first_record,
                    formats::RecordKinds known, Part& part) const {
  // Din records are 4 bytes at a multiple of 4 as Dinero IV reads them.
  std::uint64_t span_bits = 3;
  if (context_.form != formats::RecordForm::Din) {
    span_bits = 0;
    for (std::size_t i = 0; i < count; ++i) {
      const std::uint64_t address = records[i].address;
      span_bits |= address ^ (address + std::max<std::uint32_t>(records[i].size, 1) - 1);
    }
  }
  // What the reader found as it parsed them spares a pass over records
  // that have left the processor's cache. A trace whose tags are not levels
  // has only untagged records (readers read no tag then): no other streams,
  // and nothing that needs levels (the sweep refused those at its start).
  const bool levels_wanted = context_.tags_are_levels && !known.levels;
  unsigned not_demand = 0;
  unsigned not_level = context_.tags_are_levels ? 0 : 1;
  if (!known.demand_fetches || levels_wanted) {
    for (std::size_t i = 0; i < count; ++i) {
      not_demand |= static_cast<unsigned>(records[i].type > AccessType::Misc);
      not_level |= static_cast<unsigned>(records[i].tag > formats::kMaxLevel);
    }
  }
  bool demand_only = not_demand == 0;
  const bool all_levels = not_level == 0;
  if (!all_levels && context_.tags_are_levels) {
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
  rows.reserve(reported_);
  for (std::size_t s = 0; s < std::min(reported_, simulators_.size()); ++s) {
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
    if (per_level_ && s < reported_) {
      const std::size_t first = result.level_rows.size();
      simulators_[s]->append_level_rows(result.level_rows);
      for (std::size_t r = first; r < result.level_rows.size(); ++r) {
        result.level_rows[r].split_level = plan_->first(s);
      }
    }
  }
  if (per_animation_frame_) {
    for (std::size_t s = 0; s < simulators_.size(); ++s) {
      if (!open_frames_[s].open) change_frame(s, nullptr);  // a trace without records
      change_frame(s, nullptr);  // closes the last frame
    }
    // Every simulator saw the same frames: frame by frame, configurations in order.
    const std::size_t frames = animation_frame_rows_.empty() ? 0 : animation_frame_rows_[0].size();
    for (std::size_t f = 0; f < frames; ++f) {
      for (std::size_t s = 0; s < reported_; ++s) result.animation_frame_rows.push_back(animation_frame_rows_[s][f]);
    }
  }
  if (treelet_prefetch_) {
    for (std::size_t s = 0; s < reported_; ++s) {
      ResultRow& row = result.rows[s];
      if (!row.prefetch) row.prefetch = PrefetchColumns{};
      row.prefetch->misses_without_prefetch = result.rows[without_prefetch_[s]].misses;
      row.prefetch->fetched_blocks = demand_blocks_fetched(row) + row.prefetch->counts.prefetches;
    }
  }
  result.rows.resize(reported_);
  // Every part sees every record; part 0's count is the trace's.
  const std::uint64_t other_stream_records = parts_.empty() ? 0 : parts_[0].other_stream_records;
  result.other_stream_records = other_stream_records;
  result.notes = plan_->notes();
  if (treelet_prefetch_) result.notes.push_back(treelet_prefetch_note());
  if (other_stream_records > 0) {
    result.notes.push_back(other_streams_note(context_.trace, other_stream_records));
  }
  return result;
}

}  // namespace nodetrace::cachesim