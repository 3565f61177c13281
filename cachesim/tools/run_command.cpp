// cachesim run: single and split node caches, every combination of the
// listed options simulated in one pass over each trace.
#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <new>

#include "commands.hpp"
#include "nodetrace/cli/command_line.hpp"
#include "nodetrace/cli/exit_status.hpp"
#include "nodetrace/cli/progress_line.hpp"
#include "nodetrace/cachesim/sweep/curve.hpp"
#include "nodetrace/cachesim/report/report.hpp"
#include "nodetrace/cachesim/sampling/sampled_sweep.hpp"
#include "nodetrace/cachesim/sweep/sweep.hpp"
#include "nodetrace/cachesim/sweep/unit_sweep.hpp"
#include "nodetrace/cachesim/models/cache_geometry.hpp"
#include "nodetrace/base/error.hpp"
#include "nodetrace/formats/read/trace_reader.hpp"
#include "nodetrace/base/sample_rate.hpp"
#include "run_options.hpp"

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

int curve_command(const RunCommandLine& line, const SweepOptions& options) {
  if (options.split_levels.size() != 1) throw base::UsageError("--curve takes one --split-level");
  CurveOptions curve;
  curve.blocks = options.blocks;
  curve.assocs = options.assocs;
  curve.schemes = options.schemes;
  curve.policies = options.policies;
  curve.split_level = options.split_levels[0];
  curve.high_size = options.high_size;
  std::vector<CurvePoint> points;
  for (const std::string& trace : line.traces) {
    auto reader = formats::TraceReader::open(trace, reader_options(line));
    const std::vector<CurvePoint> more = run_curve(*reader, curve, trace);
    points.insert(points.end(), more.begin(), more.end());
  }
  const std::optional<std::string> repeated = merge_repeated_points(points);
  const ReportFormat format = parse_report_format(line.format).value_or(ReportFormat::Table);
  const std::string text = format_curve(points, format);
  std::fwrite(text.data(), 1, text.size(), stdout);
  print_notes(repeated ? std::vector<std::string>{*repeated} : std::vector<std::string>{}, format);
  return 0;
}

// The second-level cache of `cachesim run --l2-size`.
struct SecondLevelCommandLine {
  std::string size;
  std::uint32_t block = 64;
  std::string assoc = "8";
  std::string policy = "lru";
};

// The sampling options of `cachesim run` (dinero-wrap has none).
struct SamplingCommandLine {
  std::string windows;
  std::string sets;
  std::uint64_t window_records = kDefaultWindowRecords;
  std::uint64_t seed = 0;
};

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

using Readers = std::vector<std::unique_ptr<formats::TraceReader>>;

// Every trace opened before any is read: whether one is row-sampled decides
// the report's columns. Window sampling skips data frames from the start.
Readers open_traces(const RunCommandLine& line, const SamplingOptions& sampling) {
  formats::ReaderOptions options = reader_options(line);
  if (sampling.window_every != 0) options.keep_data_frame = data_frame_filter(sampling);
  Readers readers;
  for (const std::string& trace : line.traces) {
    readers.push_back(formats::TraceReader::open(trace, options));
  }
  return readers;
}

// The records a trace holds, when its trailer says (a seekable container).
std::optional<std::uint64_t> record_total(const formats::TraceReader& reader) {
  const auto& trailer = reader.trailer();
  if (!trailer || !trailer->totals.contains("records") || !trailer->totals["records"].is_number_unsigned()) {
    return std::nullopt;
  }
  return trailer->totals["records"].get<std::uint64_t>();
}

// The first row-sampled trace (header "sampling"), or nullptr.
const formats::TraceReader* row_sampled(const Readers& readers) {
  for (const auto& reader : readers) {
    if (reader->header().sampling()) return reader.get();
  }
  return nullptr;
}

int sampled_command(const RunCommandLine& line, const std::vector<Configuration>& configs,
                    const SamplingOptions& sampling, const Readers& readers, std::vector<std::string> notes) {
  std::vector<SampledRow> rows;
  std::vector<GainRow> gains;
  for (std::size_t t = 0; t < readers.size(); ++t) {
    SampledResult result = run_sampled_sweep(*readers[t], configs, line.traces[t], sampling);
    rows.insert(rows.end(), result.rows.begin(), result.rows.end());
    gains.insert(gains.end(), result.gains.begin(), result.gains.end());
    notes.insert(notes.end(), result.notes.begin(), result.notes.end());
  }
  const ReportFormat format = parse_report_format(line.format).value_or(ReportFormat::Table);
  const std::string report = format_sampled_report(rows, gains, format);
  std::fwrite(report.data(), 1, report.size(), stdout);
  print_notes(notes, format);
  return 0;
}

// What of --units private and --l2-size was given, for the errors about them.
std::string unit_options_given(const UnitSweepOptions& unit_options) {
  if (unit_options.private_units && unit_options.l2) return "--units private and --l2-size";
  return unit_options.private_units ? "--units private" : "--l2-size";
}

// --units private: every unit's own caches; the report sums them, and
// --per-unit writes one row per unit and configuration. --l2-size: a second
// level shared by the units, over private or shared first levels.
int unit_caches_command(const RunCommandLine& line, const SweepOptions& options,
                        const std::vector<Configuration>& configs, const Readers& readers,
                        const UnitSweepOptions& unit_options, std::vector<std::string> notes) {
  if (options.per_level || options.per_animation_frame) {
    const char* given = options.per_level && options.per_animation_frame ? "--per-level and --per-frame"
                        : options.per_level                            ? "--per-level"
                                                                       : "--per-frame";
    throw base::UsageError(fmt::format("{}: not with {} (its rows are totals over the units; --per-unit gives "
                                       "each unit's rows)",
                                       unit_options_given(unit_options), given));
  }
  if (options.fetch != FetchPolicy::Demand) {
    throw base::UsageError(fmt::format("--fetch {}: {} simulates demand fetch only", line.fetch,
                                       unit_options_given(unit_options)));
  }
  std::vector<ResultRow> rows;
  std::vector<UnitRow> unit_rows;
  for (std::size_t t = 0; t < readers.size(); ++t) {
    if (unit_options.private_units && readers[t]->units() == 1) {
      notes.push_back(fmt::format("{}: its records carry no unit (no \"units\" above 1 in a header): one unit",
                                  readers[t]->source_name()));
    }
    UnitSweepResult result = run_unit_sweep(*readers[t], configs, line.traces[t], unit_options);
    rows.insert(rows.end(), result.total.rows.begin(), result.total.rows.end());
    unit_rows.insert(unit_rows.end(), result.unit_rows.begin(), result.unit_rows.end());
    notes.insert(notes.end(), result.total.notes.begin(), result.total.notes.end());
  }
  print_report(rows, {}, notes, line, {}, unit_rows);
  return 0;
}

}  // namespace

int run_command(int argc, char** argv) {
  CLI::App app{
      "Simulate single and split node caches on traces; every combination of the listed values "
      "is simulated in one pass over each trace.\n"
      "Example: cachesim run t.din.zst --size 4k,8k,16k --scheme single,split --format csv",
      "cachesim run"};
  RunCommandLine line;
  add_run_options(app, line);
  SamplingCommandLine sampling_line;
  // cachesim run only: dinero-wrap shares the other options, and a curve has no Dinero IV run to check it.
  app.add_flag("--curve", line.curve,
               "Instead: miss ratio of every power-of-two size up to 64 MB (in --format), per --block and "
               "--assoc, single caches and the split scheme's low cache (K from --split-level, "
               "or auto for --high-size)");
  add_sampling_options(app, sampling_line);
  app.add_option("--units", line.units,
                 "Traversal units of a trace whose records carry them (header \"units\"): shared (one copy of "
                 "each cache sees every record) or private (each unit its own copy; the report sums them)")
      ->check(CLI::IsMember({"shared", "private"}))
      ->capture_default_str();
  SecondLevelCommandLine l2_line;
  app.add_option("--l2-size", l2_line.size,
                 "Add a second-level cache of this size, shared by all units, seeing each configuration's "
                 "first-level misses (and retained high-cache loads) in trace order; its own report columns");
  app.add_option("--l2-block", l2_line.block, "Second-level block size in bytes")->capture_default_str();
  app.add_option("--l2-assoc", l2_line.assoc, "Second-level ways, or full")->capture_default_str();
  app.add_option("--l2-policy", l2_line.policy, "Second-level replacement: lru or fifo")
      ->check(CLI::IsMember({"lru", "fifo"}))
      ->capture_default_str();
  app.add_option("--per-unit", line.per_unit,
                 "--units private: also write each unit's rows (the main columns, unit after trace) to FILE "
                 "(- for standard output instead of the main table)");
  if (const std::optional<int> status = nodetrace::cli::parse_command_line(app, argc, argv)) return *status;
  return nodetrace::cli::exit_status_of("cachesim run", [&] {
    const SweepOptions options = sweep_options(line);
    const SamplingOptions sampling = sampling_options(sampling_line, line);
    if (options.fetch != FetchPolicy::Demand && (line.curve || sampling.sampling())) {
      throw base::UsageError(fmt::format("--fetch {}: not with --curve or sampling, which are demand-fetch",
                                            line.fetch));
    }
    if (line.curve) {
      check_curve_options(app);
      return curve_command(line, options);
    }
    std::vector<Configuration> configs = expand_configurations(options);
    std::vector<std::string> notes;
    if (const std::optional<std::string> repeated = merge_repeated_configurations(configs)) notes.push_back(*repeated);
    const Readers readers = open_traces(line, sampling);
    if (!line.per_unit.empty() && line.units != "private") {
      throw base::UsageError("--per-unit: the rows of private caches need --units private");
    }
    UnitSweepOptions unit_options;
    unit_options.private_units = line.units == "private";
    if (!l2_line.size.empty()) {
      CacheGeometry l2;
      l2.size = cache_size(l2_line.size, "--l2-size");
      l2.block_size = l2_line.block;
      l2.assoc = parse_assoc(l2_line.assoc);  // 0: full
      if (l2.assoc == 0) l2.assoc = static_cast<std::uint32_t>(l2.size / std::max(1u, l2.block_size));
      l2.replacement = parse_policy_name(l2_line.policy).value_or(ReplacementPolicy::Lru);
      unit_options.l2 = l2;
    } else if (app.count("--l2-block") + app.count("--l2-assoc") + app.count("--l2-policy") > 0) {
      throw base::UsageError("--l2-block, --l2-assoc and --l2-policy describe the cache --l2-size adds");
    }
    if (unit_options.private_units || unit_options.l2) {
      if (sampling.sampling() || row_sampled(readers)) {
        throw base::UsageError(fmt::format("{}: not with sampling (--sample-windows, --sample-sets or a row-sampled "
                                           "trace)",
                                           unit_options_given(unit_options)));
      }
      return unit_caches_command(line, options, configs, readers, unit_options, notes);
    }
    if (const formats::TraceReader* sampled = row_sampled(readers)) {
      if (!line.per_level.empty() || !line.per_animation_frame.empty()) {
        throw base::UsageError(fmt::format(
            "{} is row-sampled (header \"sampling\"): not with --per-level or --per-frame",
            sampled->source_name()));
      }
    }
    if (sampling.sampling() || row_sampled(readers)) {
      if (options.fetch != FetchPolicy::Demand) {
        throw base::UsageError(fmt::format("--fetch {}: not on a row-sampled trace (demand-fetch only)",
                                              line.fetch));
      }
      return sampled_command(line, configs, sampling, readers, notes);
    }
    std::vector<ResultRow> rows;
    std::vector<LevelRow> levels;
    std::vector<AnimationFrameRow> frames;
    nodetrace::cli::ProgressLine progress_line;
    std::string current_trace;
    std::optional<std::uint64_t> current_total;
    SweepProgress progress;
    if (progress_line.shown()) {
      progress = [&](std::uint64_t records_read) {
        progress_line.update_count(current_trace, records_read, current_total, "records");
      };
    }
    for (std::size_t t = 0; t < readers.size(); ++t) {
      const std::string& trace = line.traces[t];
      current_trace = trace;
      current_total = record_total(*readers[t]);
      progress_line.restart();
      TraceResult result =
          run_sweep(*readers[t], configs, trace, options.per_level, progress, options.per_animation_frame);
      progress_line.clear();
      rows.insert(rows.end(), result.rows.begin(), result.rows.end());
      levels.insert(levels.end(), result.level_rows.begin(), result.level_rows.end());
      frames.insert(frames.end(), result.animation_frame_rows.begin(), result.animation_frame_rows.end());
      notes.insert(notes.end(), result.notes.begin(), result.notes.end());
    }
    print_report(rows, levels, notes, line, frames);
    return 0;
  }, kTooLarge);
}

}  // namespace nodetrace::cachesim::tools
