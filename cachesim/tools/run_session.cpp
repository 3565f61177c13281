#include "run_session.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <optional>
#include <utility>

#include "nodetrace/base/available_memory.hpp"
#include "nodetrace/base/error.hpp"
#include "nodetrace/base/sample_rate.hpp"
#include "nodetrace/cachesim/models/cache_geometry.hpp"
#include "nodetrace/cachesim/report/report.hpp"
#include "nodetrace/cachesim/sweep/state_memory.hpp"

namespace nodetrace::cachesim::tools {

namespace {

// --curve answers every power-of-two size of single and low caches: these
// options have nothing to set there, and one silently ignored misleads.
void check_curve_options(const CLI::App& app) {
  for (const char* option : {"--size", "--high-policy", "--low-size", "--high-assoc", "--count-loads", "--per-level",
                             "--per-frame", "--units", "--per-unit"}) {
    if (app.count(option) > 0) {
      throw base::UsageError(fmt::format(
          "{} does not apply to --curve (it covers every power-of-two size up to 64 MB, single caches and the "
          "split scheme's low cache); --curve takes --block, --assoc, --policy, --scheme, --split-level, "
          "--high-size, --format",
          option));
    }
  }
}

CurveOptions curve_options(const SweepOptions& options) {
  if (options.split_levels.size() != 1) throw base::UsageError("--curve takes one --split-level");
  CurveOptions curve;
  curve.blocks = options.blocks;
  curve.assocs = options.assocs;
  curve.schemes = options.schemes;
  curve.policies = options.policies;
  curve.split_level = options.split_levels[0];
  curve.high_size = options.high_size;
  return curve;
}

// What of --units private and --l2-size was given, for the errors about them.
std::string unit_options_given(const UnitSweepOptions& unit_options) {
  if (unit_options.private_units && unit_options.l2) return "--units private and --l2-size";
  return unit_options.private_units ? "--units private" : "--l2-size";
}

void add_sampling_options(CLI::App& app, SamplingCommandLine& line) {
  app.add_option("--sample-windows", line.windows,
                 "Simulate one window of records in every K (1/K), chosen by --sample-seed; the "
                 "report gains each miss ratio's standard error and 95% interval");
  app.add_option("--window-records", line.window_records,
                 "Records per window of --sample-windows (default: one container data frame)")
      ->capture_default_str();
  app.add_option("--sample-sets", line.sets,
                 "Simulate the blocks of one cache set in every K (1/K, K a power of two); needs one --block and "
                 "power-of-two set counts of at least K");
  app.add_option("--sample-seed", line.seed, "Seed of the sampled windows and sets")
      ->capture_default_str();
}

SamplingOptions sampling_options(const SamplingCommandLine& line, const RunCommandLine& run) {
  SamplingOptions options;
  if (!line.windows.empty()) options.window_every = base::parse_sample_rate(line.windows, "--sample-windows");
  if (!line.sets.empty()) options.set_every = base::parse_sample_rate(line.sets, "--sample-sets");
  if (line.window_records == 0) {
    throw base::UsageError("--window-records: 0 is not a window length: expected at least 1");
  }
  options.window_records = line.window_records;
  options.seed = line.seed;
  if (options.sampling() && (!run.per_level.empty() || !run.per_animation_frame.empty() || run.curve)) {
    throw base::UsageError(
        "--sample-windows / --sample-sets: not with --per-level, --per-frame or --curve");
  }
  return options;
}

// The first row-sampled trace (header "sampling"), or nullptr.
const formats::TraceReader* row_sampled(const std::vector<const formats::TraceReader*>& readers) {
  for (const auto* reader : readers) {
    if (reader->header().sampling()) return reader;
  }
  return nullptr;
}

template <typename T>
void append(std::vector<T>& to, const std::vector<T>& from) {
  to.insert(to.end(), from.begin(), from.end());
}

}  // namespace

void RunSession::add_options(CLI::App& app, bool traces_positional) {
  add_run_options(app, line_, true, traces_positional);
  // cachesim run only: dinero-wrap shares the other options, and a curve has no Dinero IV run to check it.
  app.add_flag("--curve", line_.curve,
               "Instead: miss ratio of every power-of-two size up to 64 MB (in --format), per --block and "
               "--assoc, single caches and the split scheme's low cache (K from --split-level, "
               "or auto for --high-size)");
  add_sampling_options(app, sampling_line_);
  app.add_option("--units", line_.units,
                 "Traversal units of a trace whose records carry them (header \"units\"): shared (one copy of "
                 "each cache sees every record) or private (each unit its own copy; the report sums them)")
      ->check(CLI::IsMember({"shared", "private"}))
      ->capture_default_str();
  app.add_option("--l2-size", l2_line_.size,
                 "Add a second-level cache of this size, shared by all units, seeing each configuration's "
                 "first-level misses (and retained high-cache loads) in trace order; its own report columns");
  app.add_option("--l2-block", l2_line_.block, "Second-level block size in bytes")->capture_default_str();
  app.add_option("--l2-assoc", l2_line_.assoc, "Second-level ways, or full")->capture_default_str();
  app.add_option("--l2-policy", l2_line_.policy, "Second-level replacement: lru or fifo")
      ->check(CLI::IsMember({"lru", "fifo"}))
      ->capture_default_str();
  app.add_option("--prefetch", prefetch_line_,
                 "Treelet prefetcher (list): none, treelet[:BYTES] (on a demand miss, the rest of the missed "
                 "block's treelet, at most BYTES from the block on, a power of two, into the cache that missed) or "
                 "treelet-low[:BYTES] (into the split scheme's low-level cache only); needs a trace with a treelet "
                 "map (tracer render --layout treelet); adds the prefetch columns; timing not modelled")
      ->delimiter(',');
  app.add_option("--per-unit", line_.per_unit,
                 "--units private: also write each unit's rows (the main columns, unit after trace) to FILE "
                 "(- for standard output instead of the main table)");
}

void RunSession::prepare(const CLI::App& app) {
  options_ = sweep_options(line_);
  if (!prefetch_line_.empty()) {
    options_.prefetches.clear();
    for (const std::string& text : prefetch_line_) options_.prefetches.push_back(parse_prefetch(text));
  }
  sampling_ = sampling_options(sampling_line_, line_);
  if (!prefetch_line_.empty()) {
    for (const char* option : {"--curve", "--sample-windows", "--sample-sets", "--units", "--l2-size"}) {
      if (app.count(option) > 0 && !(std::string_view(option) == "--units" && line_.units == "shared")) {
        throw base::UsageError(fmt::format("--prefetch: not with {} (the prefetcher runs in the plain sweep of "
                                           "shared caches)",
                                           option));
      }
    }
    if (prefetch_line_.size() > 1 && (!line_.per_level.empty() || !line_.per_animation_frame.empty())) {
      throw base::UsageError("--prefetch with more than one value: not with --per-level or --per-frame (their rows "
                             "do not name the prefetcher); give one --prefetch value");
    }
  }
  if (options_.fetch != FetchPolicy::Demand && (line_.curve || sampling_.sampling())) {
    throw base::UsageError(fmt::format("--fetch {}: not with --curve or sampling, which are demand-fetch",
                                       line_.fetch));
  }
  if (line_.curve) {
    check_curve_options(app);
    curve_options(options_);
    return;
  }
  configs_ = expand_configurations(options_);
  if (const std::optional<std::string> split_size = split_size_note(line_, options_)) {
    configuration_notes_.push_back(*split_size);
  }
  if (const std::optional<std::string> repeated = merge_repeated_configurations(configs_)) {
    configuration_notes_.push_back(*repeated);
  }
  if (!line_.per_unit.empty() && line_.units != "private") {
    throw base::UsageError("--per-unit: the rows of private caches need --units private");
  }
  unit_options_.private_units = line_.units == "private";
  if (!l2_line_.size.empty()) {
    CacheGeometry l2;
    l2.size = cache_size(l2_line_.size, "--l2-size");
    l2.block_size = l2_line_.block;
    l2.assoc = assoc_option(l2_line_.assoc, "--l2-assoc");  // 0: full
    if (l2.assoc == 0) l2.assoc = static_cast<std::uint32_t>(l2.size / std::max(1u, l2.block_size));
    l2.replacement = parse_policy_name(l2_line_.policy).value_or(ReplacementPolicy::Lru);
    unit_options_.l2 = l2;
  } else if (app.count("--l2-block") + app.count("--l2-assoc") + app.count("--l2-policy") > 0) {
    throw base::UsageError("--l2-block, --l2-assoc and --l2-policy describe the cache --l2-size adds");
  }
  if (unit_options_.private_units || unit_options_.l2) {
    if (options_.per_level || options_.per_animation_frame) {
      const char* given = options_.per_level && options_.per_animation_frame ? "--per-level and --per-frame"
                          : options_.per_level                             ? "--per-level"
                                                                           : "--per-frame";
      throw base::UsageError(fmt::format("{}: not with {} (its rows are totals over the units; --per-unit gives "
                                         "each unit's rows)",
                                         unit_options_given(unit_options_), given));
    }
    if (options_.fetch != FetchPolicy::Demand) {
      throw base::UsageError(fmt::format("--fetch {}: {} simulates demand fetch only", line_.fetch,
                                         unit_options_given(unit_options_)));
    }
  }
  check_state_memory();
}

namespace {

std::string mebibytes(std::uint64_t bytes) { return fmt::format("{} MiB", (bytes + (1u << 20) - 1) >> 20); }

}  // namespace

void RunSession::check_state_memory() {
  // Large caches cost their memory (and the time to write it) before the
  // first record: said before the run, and refused where it cannot fit.
  constexpr std::uint64_t kNotedBytes = std::uint64_t{256} << 20;
  const std::uint64_t state = state_bytes(configs_, unit_options_.l2 ? &*unit_options_.l2 : nullptr);
  const char* per_unit = unit_options_.private_units ? ", per traversal unit" : "";
  if (const std::optional<std::uint64_t> available = base::available_memory_bytes(); available && state > *available) {
    throw base::UsageError(fmt::format(
        "the caches asked for keep about {} of state{}, allocated before the first record, more than the {} "
        "this process may take: give fewer or smaller caches (sets of at most 16 ways keep about 8 bytes a block, "
        "of more about 48)",
        mebibytes(state), per_unit, mebibytes(*available)));
  }
  if (state >= kNotedBytes) {
    configuration_notes_.push_back(fmt::format(
        "the caches keep about {} of state{}, allocated before the first record", mebibytes(state), per_unit));
  }
}

formats::ReaderOptions RunSession::reader_options() const {
  formats::ReaderOptions options = tools::reader_options(line_);
  // Window sampling skips data frames from the start.
  if (sampling_.window_every != 0) options.keep_data_frame = data_frame_filter(sampling_);
  return options;
}

RunMode RunSession::mode_for(const std::vector<const formats::TraceReader*>& readers) const {
  if (line_.curve) return RunMode::Curve;
  const formats::TraceReader* sampled = row_sampled(readers);
  if (unit_options_.private_units || unit_options_.l2) {
    if (sampling_.sampling() || sampled) {
      throw base::UsageError(fmt::format("{}: not with sampling (--sample-windows, --sample-sets or a row-sampled "
                                         "trace)",
                                         unit_options_given(unit_options_)));
    }
    return RunMode::UnitCaches;
  }
  if (sampled && (!line_.per_level.empty() || !line_.per_animation_frame.empty())) {
    throw base::UsageError(fmt::format("{} is row-sampled (header \"sampling\"): not with --per-level or --per-frame",
                                       sampled->source_name()));
  }
  if (sampling_.sampling() || sampled) {
    if (!prefetch_line_.empty() && sampled) {
      throw base::UsageError(fmt::format("--prefetch: not on a row-sampled trace ({})", sampled->source_name()));
    }
    if (options_.fetch != FetchPolicy::Demand) {
      throw base::UsageError(fmt::format("--fetch {}: not on a row-sampled trace (demand-fetch only)", line_.fetch));
    }
    return RunMode::Sampled;
  }
  return RunMode::Sweep;
}

TraceOutcome RunSession::simulate(RunMode mode, formats::TraceReader& reader, const std::string& trace_column,
                                  const SweepProgress& progress) const {
  TraceOutcome outcome;
  switch (mode) {
    case RunMode::Curve:
      outcome.curve = run_curve(reader, curve_options(options_), trace_column);
      break;
    case RunMode::UnitCaches: {
      // One unit's private caches are the shared ones. A header that says
      // one unit (a sweep over unit counts from 1) gets a plain note; a
      // trace without a header (plain text, e.g. converted from a container
      // of several units) cannot say, and a "private" report of it would be
      // the shared result under another label: an error.
      if (unit_options_.private_units && reader.units() == 1) {
        if (!reader.header().present()) {
          throw base::UsageError(fmt::format(
              "--units private: {}: a trace without a header is one traversal unit (its records' unit fields, if "
              "any, are not read): private caches would be the shared one; give the container the tracer wrote, "
              "or leave --units out",
              reader.source_name()));
        }
        outcome.sweep.notes.push_back(fmt::format(
            "{}: one traversal unit (no \"units\" above 1 in its header): its private caches are the shared ones",
            reader.source_name()));
      }
      UnitSweepResult result = run_unit_sweep(reader, configs_, trace_column, unit_options_);
      append(outcome.sweep.rows, result.total.rows);
      append(outcome.sweep.notes, result.total.notes);
      outcome.unit_rows = std::move(result.unit_rows);
      break;
    }
    case RunMode::Sampled:
      outcome.sampled = run_sampled_sweep(reader, configs_, trace_column, sampling_);
      break;
    case RunMode::Sweep:
      outcome.sweep = run_sweep(reader, configs_, trace_column, options_.per_level, progress,
                                options_.per_animation_frame);
      break;
  }
  return outcome;
}

namespace {

// A run fed batch by batch (a Sweep or a FedSampledSweep), its result the outcome's `Member`.
template <typename Run, auto Member>
class FedRun final : public FedSimulation {
 public:
  template <typename... Args>
  explicit FedRun(Args&&... args) : run_(std::forward<Args>(args)...) {}
  Run& run() { return run_; }
  void feed(const formats::RecordBatch& batch) override { run_.feed(batch); }
  TraceOutcome finish() override {
    TraceOutcome outcome;
    outcome.*Member = run_.finish();
    return outcome;
  }

 private:
  Run run_;
};

}  // namespace

std::unique_ptr<FedSimulation> RunSession::fed_simulation(RunMode mode, const formats::TraceReader& source,
                                                          const std::string& trace_column) const {
  switch (mode) {
    case RunMode::Sweep: {
      auto fed = std::make_unique<FedRun<Sweep, &TraceOutcome::sweep>>(
          configs_, trace_context(source, trace_column), options_.per_level, options_.per_animation_frame);
      fed->run().set_parts(1);
      return fed;
    }
    case RunMode::Sampled:
      return std::make_unique<FedRun<FedSampledSweep, &TraceOutcome::sampled>>(source, configs_, trace_column,
                                                                               sampling_);
    case RunMode::Curve:
    case RunMode::UnitCaches:
      break;
  }
  return nullptr;
}

RunReport RunSession::report(RunMode mode, const std::vector<TraceOutcome>& outcomes) const {
  const ReportFormat format = parse_report_format(line_.format).value_or(ReportFormat::Table);
  if (mode == RunMode::Curve) {
    std::vector<CurvePoint> points;
    for (const auto& outcome : outcomes) append(points, outcome.curve);
    const std::optional<std::string> repeated = merge_repeated_points(points);
    RunReport report{format_curve(points, format), {}};
    add_notes(report, repeated ? std::vector<std::string>{*repeated} : std::vector<std::string>{}, format);
    return report;
  }
  if (mode == RunMode::Sampled) {
    std::vector<SampledRow> rows;
    std::vector<GainRow> gains;
    std::vector<std::string> notes = configuration_notes_;
    for (const auto& outcome : outcomes) {
      append(rows, outcome.sampled.rows);
      append(gains, outcome.sampled.gains);
      append(notes, outcome.sampled.notes);
    }
    RunReport report{format_sampled_report(rows, gains, format), {}};
    add_notes(report, notes, format);
    return report;
  }
  std::vector<ResultRow> rows;
  std::vector<LevelRow> levels;
  std::vector<AnimationFrameRow> frames;
  std::vector<UnitRow> unit_rows;
  std::vector<std::string> notes = configuration_notes_;
  for (const auto& outcome : outcomes) {
    append(rows, outcome.sweep.rows);
    append(levels, outcome.sweep.level_rows);
    append(frames, outcome.sweep.animation_frame_rows);
    append(unit_rows, outcome.unit_rows);
    append(notes, outcome.sweep.notes);
  }
  if (mode == RunMode::UnitCaches) return run_report(rows, {}, notes, line_, {}, unit_rows);
  return run_report(rows, levels, notes, line_, frames);
}

}  // namespace nodetrace::cachesim::tools
