#include "nodetrace/cachesim/simulation/simulation.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <optional>
#include <utility>

#include "nodetrace/base/available_memory.hpp"
#include "nodetrace/base/error.hpp"
#include "nodetrace/base/output_file.hpp"
#include "nodetrace/base/sample_rate.hpp"
#include "nodetrace/cachesim/models/cache_geometry.hpp"
#include "nodetrace/cachesim/report/report.hpp"
#include "nodetrace/cachesim/sweep/state_memory.hpp"
#include "option_values.hpp"

namespace nodetrace::cachesim {

namespace {

// --curve answers every power-of-two size of single and low caches: these
// options have nothing to set there, and one silently ignored misleads.
void check_curve_options(const SimulationOptions& line) {
  const std::pair<const char*, bool> given[] = {
      {"--size", line.sizes_given},          {"--high-policy", line.high_policies_given},
      {"--low-size", !line.low_size.empty()}, {"--high-assoc", !line.high_assoc.empty()},
      {"--count-loads", line.count_loads},    {"--per-level", !line.per_level.empty()},
      {"--per-frame", !line.per_frame.empty()}, {"--units", line.units.has_value()},
      {"--per-unit", !line.per_unit.empty()}};
  for (const auto& [option, is_given] : given) {
    if (is_given) {
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

SamplingOptions sampling_options(const SimulationOptions& line) {
  SamplingOptions options;
  if (!line.sample_windows.empty()) {
    options.window_every = base::parse_sample_rate(line.sample_windows, "--sample-windows");
  }
  if (!line.sample_sets.empty()) options.set_every = base::parse_sample_rate(line.sample_sets, "--sample-sets");
  if (line.window_records == 0) {
    throw base::UsageError("--window-records: 0 is not a window length: expected at least 1");
  }
  options.window_records = line.window_records;
  options.seed = line.sample_seed;
  if (options.sampling() && (!line.per_level.empty() || !line.per_frame.empty() || line.curve)) {
    throw base::UsageError(
        "--sample-windows / --sample-sets: not with --per-level, --per-frame or --curve");
  }
  return options;
}

// The values the command line takes from a fixed list (run_arguments.cpp
// checks them there, in CLI11's words): a caller that fills the struct
// itself gets a message naming the option.
void check_named_values(const SimulationOptions& line) {
  const auto check = [](const char* option, const std::string& value, std::vector<std::string> names) {
    if (std::find(names.begin(), names.end(), value) != names.end()) return;
    std::string list;
    for (const auto& name : names) list += (list.empty() ? "" : ", ") + name;
    throw base::UsageError(fmt::format("{}: '{}' is not one of {}", option, value, list));
  };
  check("--format", line.format, {"table", "csv", "json"});
  check("--units", line.units_or_default(), {"shared", "private"});
  if (line.l2_policy) check("--l2-policy", *line.l2_policy, {"lru", "fifo"});
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

std::string mebibytes(std::uint64_t bytes) { return fmt::format("{} MiB", (bytes + (1u << 20) - 1) >> 20); }

}  // namespace

SimulationPlan::SimulationPlan(SimulationOptions options) : line_(std::move(options)) {
  check_named_values(line_);
  options_ = sweep_options(line_);
  sampling_ = sampling_options(line_);
  if (!line_.prefetch.empty()) {
    options_.prefetches.clear();
    for (const std::string& text : line_.prefetch) options_.prefetches.push_back(parse_prefetch(text));
    const char* refused = line_.curve                                  ? "--curve"
                          : !line_.sample_windows.empty()              ? "--sample-windows"
                          : !line_.sample_sets.empty()                 ? "--sample-sets"
                          : line_.units_or_default() == "private"      ? "--units"
                          : !line_.l2_size.empty()                     ? "--l2-size"
                                                                       : nullptr;
    if (refused != nullptr) {
      throw base::UsageError(fmt::format(
          "--prefetch: not with {} (the prefetcher runs in the plain sweep of shared caches)", refused));
    }
    if (line_.prefetch.size() > 1 && (!line_.per_level.empty() || !line_.per_frame.empty())) {
      throw base::UsageError("--prefetch with more than one value: not with --per-level or --per-frame (their rows "
                             "do not name the prefetcher); give one --prefetch value");
    }
  }
  if (options_.fetch != FetchPolicy::Demand && (line_.curve || sampling_.sampling())) {
    throw base::UsageError(fmt::format("--fetch {}: not with --curve or sampling, which are demand-fetch",
                                       line_.fetch));
  }
  if (line_.curve) {
    check_curve_options(line_);
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
  if (!line_.per_unit.empty() && line_.units_or_default() != "private") {
    throw base::UsageError("--per-unit: the rows of private caches need --units private");
  }
  unit_options_.private_units = line_.units_or_default() == "private";
  if (!line_.l2_size.empty()) {
    CacheGeometry l2;
    l2.size = cache_size(line_.l2_size, "--l2-size");
    l2.block_size = line_.l2_block.value_or(64);
    l2.assoc = assoc_option(line_.l2_assoc.value_or("8"), "--l2-assoc");  // 0: full
    if (l2.assoc == 0) l2.assoc = static_cast<std::uint32_t>(l2.size / std::max(1u, l2.block_size));
    l2.replacement = parse_policy_name(line_.l2_policy.value_or("lru")).value_or(ReplacementPolicy::Lru);
    unit_options_.l2 = l2;
  } else if (line_.l2_block || line_.l2_assoc || line_.l2_policy) {
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

void SimulationPlan::check_state_memory() {
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

formats::ReaderOptions SimulationPlan::reader_options() const {
  formats::ReaderOptions options = cachesim::reader_options(line_);
  // Window sampling skips data frames from the start.
  if (sampling_.window_every != 0) options.keep_data_frame = data_frame_filter(sampling_);
  return options;
}

SimulationMode SimulationPlan::mode_for(const std::vector<const formats::TraceReader*>& readers) const {
  if (line_.curve) return SimulationMode::Curve;
  const formats::TraceReader* sampled = row_sampled(readers);
  if (unit_options_.private_units || unit_options_.l2) {
    if (sampling_.sampling() || sampled) {
      throw base::UsageError(fmt::format("{}: not with sampling (--sample-windows, --sample-sets or a row-sampled "
                                         "trace)",
                                         unit_options_given(unit_options_)));
    }
    return SimulationMode::UnitCaches;
  }
  if (sampled && (!line_.per_level.empty() || !line_.per_frame.empty())) {
    throw base::UsageError(fmt::format("{} is row-sampled (header \"sampling\"): not with --per-level or --per-frame",
                                       sampled->source_name()));
  }
  if (sampling_.sampling() || sampled) {
    if (!line_.prefetch.empty() && sampled) {
      throw base::UsageError(fmt::format("--prefetch: not on a row-sampled trace ({})", sampled->source_name()));
    }
    if (options_.fetch != FetchPolicy::Demand) {
      throw base::UsageError(fmt::format("--fetch {}: not on a row-sampled trace (demand-fetch only)", line_.fetch));
    }
    return SimulationMode::Sampled;
  }
  return SimulationMode::Sweep;
}

TraceOutcome SimulationPlan::simulate(SimulationMode mode, formats::TraceReader& reader,
                                      const std::string& trace_column, const SweepProgress& progress) const {
  TraceOutcome outcome;
  switch (mode) {
    case SimulationMode::Curve:
      outcome.curve = run_curve(reader, curve_options(options_), trace_column);
      break;
    case SimulationMode::UnitCaches: {
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
    case SimulationMode::Sampled:
      outcome.sampled = run_sampled_sweep(reader, configs_, trace_column, sampling_);
      break;
    case SimulationMode::Sweep:
      outcome.sweep = run_sweep(reader, configs_, trace_column, options_.per_level, progress,
                                options_.per_animation_frame);
      break;
  }
  return outcome;
}

namespace {

// A run fed batch by batch (a Sweep or a FedSampledSweep), its result the outcome's `Member`.
template <typename Run, auto Member>
class FedRun final : public Simulation {
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

std::unique_ptr<Simulation> SimulationPlan::start(SimulationMode mode, const formats::TraceReader& source,
                                                  const std::string& trace_column) const {
  switch (mode) {
    case SimulationMode::Sweep: {
      auto fed = std::make_unique<FedRun<Sweep, &TraceOutcome::sweep>>(
          configs_, trace_context(source, trace_column), options_.per_level, options_.per_animation_frame);
      fed->run().set_parts(1);
      return fed;
    }
    case SimulationMode::Sampled:
      return std::make_unique<FedRun<FedSampledSweep, &TraceOutcome::sampled>>(source, configs_, trace_column,
                                                                               sampling_);
    case SimulationMode::Curve:
    case SimulationMode::UnitCaches:
      break;
  }
  return nullptr;
}

namespace {

// Notes go under a table, or on standard error so that CSV and JSON stay
// machine-readable.
void add_notes(SimulationReport& report, const std::vector<std::string>& notes, ReportFormat format) {
  for (const std::string& note : notes) {
    (format == ReportFormat::Table ? report.out : report.err) += fmt::format("note: {}\n", note);
  }
}

// The format of a side table's file: a name ending in .csv or .json says
// it (docs/guide/caches.md: --per-frame frames.csv), any other name and "-" take --format.
ReportFormat table_file_format(const std::string& path, ReportFormat format) {
  if (path.ends_with(".csv")) return ReportFormat::Csv;
  if (path.ends_with(".json")) return ReportFormat::Json;
  return format;
}

// Writes one table to `path` ("-": the report's own output), whole or not at all.
void write_table(const std::string& path, const std::string& text, SimulationReport& report) {
  if (path == "-") {
    report.out += text;
    return;
  }
  base::OutputFile file(path);
  file.write(text);
  file.commit();
}

}  // namespace

// Each table is an output of its own: the main one in `out`, unless
// --per-level - or --per-frame - puts that table there instead; the others
// in their files.
SimulationReport sweep_report(const std::vector<ResultRow>& rows, const std::vector<LevelRow>& levels,
                              const std::vector<std::string>& notes, const SimulationOptions& line,
                              const std::vector<AnimationFrameRow>& frames, const std::vector<UnitRow>& unit_rows) {
  SimulationReport report;
  const ReportFormat format = parse_report_format(line.format).value_or(ReportFormat::Table);
  if (!line.per_level.empty()) {
    write_table(line.per_level, format_level_rows(levels, table_file_format(line.per_level, format)), report);
  }
  if (!line.per_frame.empty()) {
    write_table(line.per_frame, format_animation_frame_rows(frames, table_file_format(line.per_frame, format)),
                report);
  }
  if (!line.per_unit.empty()) {
    write_table(line.per_unit, format_unit_rows(unit_rows, table_file_format(line.per_unit, format)), report);
  }
  if (line.per_level != "-" && line.per_frame != "-" && line.per_unit != "-") {
    report.out += format_rows(rows, format);
  }
  std::vector<std::string> all_notes = notes;
  if (line.fetch != "demand") {
    all_notes.push_back(fmt::format("fetch policy {}, prefetch distance {}: fetches and misses are demand "
                                    "ones, as Dinero IV counts them (prefetches are not counted)",
                                    line.fetch, line.prefetch_distance));
  }
  add_notes(report, all_notes, format);
  return report;
}

SimulationReport SimulationPlan::report(SimulationMode mode, const std::vector<TraceOutcome>& outcomes) const {
  const ReportFormat format = parse_report_format(line_.format).value_or(ReportFormat::Table);
  if (mode == SimulationMode::Curve) {
    std::vector<CurvePoint> points;
    for (const auto& outcome : outcomes) append(points, outcome.curve);
    const std::optional<std::string> repeated = merge_repeated_points(points);
    SimulationReport report{format_curve(points, format), {}};
    add_notes(report, repeated ? std::vector<std::string>{*repeated} : std::vector<std::string>{}, format);
    return report;
  }
  if (mode == SimulationMode::Sampled) {
    std::vector<SampledRow> rows;
    std::vector<GainRow> gains;
    std::vector<std::string> notes = configuration_notes_;
    for (const auto& outcome : outcomes) {
      append(rows, outcome.sampled.rows);
      append(gains, outcome.sampled.gains);
      append(notes, outcome.sampled.notes);
    }
    SimulationReport report{format_sampled_report(rows, gains, format), {}};
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
  if (mode == SimulationMode::UnitCaches) return sweep_report(rows, {}, notes, line_, {}, unit_rows);
  return sweep_report(rows, levels, notes, line_, frames);
}

}  // namespace nodetrace::cachesim
