// The options shared by `cachesim run` and `dinero-wrap run`, so both tools
// take the same command line and print the same report.
#pragma once

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <charconv>
#include <string_view>
#include <cstdio>
#include <string>
#include <vector>

#include "nodetrace/cachesim/report/report.hpp"
#include "nodetrace/cachesim/sweep/sweep.hpp"
#include "nodetrace/base/byte_size.hpp"
#include "nodetrace/base/error.hpp"
#include "nodetrace/base/output_file.hpp"
#include "nodetrace/cli/distinct_outputs.hpp"
#include "nodetrace/cli/format_option.hpp"
#include "nodetrace/cli/option_limits.hpp"
#include "nodetrace/formats/read/trace_reader.hpp"

namespace nodetrace::cachesim::tools {

// The largest cache a run simulates (--size, --high-size, --low-size): the
// simulator allocates its blocks' state up front, so the limit bounds the
// memory of each cache whatever the trace's length; the run's total is
// stated and checked before it starts (RunSession::check_state_memory).
inline constexpr std::uint64_t kMaxCacheBytes = std::uint64_t{256} << 20;
// And the most blocks one cache holds (256m of 8-byte blocks), so small
// blocks cannot multiply that memory.
inline constexpr std::uint64_t kMaxCacheBlocks = kMaxCacheBytes / 8;

inline std::uint64_t cache_size(const std::string& text, const char* option) {
  return cli::check_at_most(base::parse_byte_size(text, option), kMaxCacheBytes, option, text, "256m",
                                "the largest cache: its state is allocated up front");
}

// parse_assoc's value, its message naming `option` (--assoc 0 is a usage
// error of --assoc, not of some associativity).
inline std::uint32_t assoc_option(const std::string& text, const char* option) {
  try {
    return parse_assoc(text);
  } catch (const base::UsageError& error) {
    throw base::UsageError(fmt::format("{}: {}", option, error.what()));
  }
}

// Sizes and blocks are powers of two (a cache's sets, ways and blocks are):
// refused naming the option and the value as typed.
inline void check_power_of_two(std::uint64_t value, const std::string& text, const char* option) {
  if (!std::has_single_bit(value)) {
    throw base::UsageError(fmt::format("{} {}: {} bytes is not a power of two (a cache's size and blocks are)",
                                       option, text, value));
  }
}

struct RunCommandLine {
  std::vector<std::string> traces;
  std::vector<std::string> sizes{"8k"};
  bool sizes_given = false;  // --size on the command line, not its default
  std::vector<std::string> blocks{"8"};
  std::vector<std::string> assocs{"1"};
  std::vector<std::string> policies{"lru"};
  std::vector<std::string> schemes{"single"};
  std::vector<std::string> split_levels{"auto"};
  std::vector<std::string> high_policies{"retain"};
  std::string high_size;
  std::string low_size;
  std::string high_assoc;
  bool count_loads = false;
  std::string fetch = "demand";
  unsigned prefetch_distance = 1;
  bool tags_are_levels = false;
  std::string per_level;            // --per-level FILE: the per-level table's output ("" = none, "-" = stdout)
  std::string per_animation_frame;  // --per-frame FILE: likewise
  std::string units = "shared";     // cachesim run --units: shared or private caches per traversal unit
  std::string per_unit;             // --per-unit FILE: likewise (--units private)
  bool curve = false;
  std::string format = "table";
  std::string informat;  // plain traces: din, xdin, binary
  unsigned threads = 0;  // decoding threads; 0 = one per core
};

// --policy's description. `cachesim_run`: the policies Dinero IV does not have too.
inline std::string policy_help(bool cachesim_run) {
  if (!cachesim_run) {
    return "Replacement: lru, fifo, random (list); random draws Dinero IV's sequence. The other policies "
           "of cachesim run (plru, srrip, brrip, drrip, opt) are not Dinero IV's: not here";
  }
  return "Replacement (list): lru, fifo, random (Dinero IV's: random draws its sequence, glibc's random() "
         "after srandom(1), one generator per cache); plru (tree pseudo-LRU, power-of-two ways); srrip "
         "(2-bit RRIP: insert at 2, 0 on a hit, victim the first way at 3 after ageing the set); brrip (insert "
         "at 3 but every 32nd insertion of the cache at 2: the 32nd, 64th, ...); drrip (set dueling, 10-bit "
         "PSEL from 511: of S sets, min(32, S/2) runs of consecutive sets, each run's first set an srrip "
         "leader and its last a brrip leader; other sets brrip while PSEL >= 512); opt (Belady's MIN: on a "
         "miss in a full set the block whose next use is farthest, never used again counting as farthest, "
         "is kept out, the incoming one included: it is then not placed; MIN within each set; the trace is "
         "read once and its fetches kept, 8 bytes each). A miss fills the lowest invalid way first";
}

// `side_tables`: --per-level and --per-frame (cachesim run only: Dinero IV
// reports totals, so dinero-wrap does not list options that cannot work).
// `traces_positional`: false for a caller that gives the traces itself
// (tracer render --simulate: the render's records).
inline void add_run_options(CLI::App& app, RunCommandLine& line, bool side_tables = true,
                            bool traces_positional = true) {
  if (traces_positional) {
    app.add_option("traces", line.traces, "Trace files (container, plain din / xdin, zstd); - is stdin")
        ->required();
  }
  app.add_option("--size", line.sizes, "Total cache sizes, bytes with optional k/m, at most 256m (list)")
      ->delimiter(',')
      ->capture_default_str()
      ->each([&line](const std::string&) { line.sizes_given = true; });
  app.add_option("--block", line.blocks, "Block sizes in bytes (list)")
      ->delimiter(',')
      ->capture_default_str();
  app.add_option("--assoc", line.assocs, "Associativities: ways or 'full' (list)")
      ->delimiter(',')
      ->capture_default_str();
  app.add_option("--policy", line.policies, policy_help(side_tables))
      ->delimiter(',')
      ->capture_default_str();
  app.add_option("--scheme", line.schemes, "single, split (list)")
      ->delimiter(',')
      ->capture_default_str();
  app.add_option("--split-level", line.split_levels,
                 "K: levels < K go to the high-level cache; 'auto' sizes K to the high cache "
                 "from the animation-frame markers (list)")
      ->delimiter(',')
      ->capture_default_str();
  app.add_option("--high-policy", line.high_policies,
                 "High-level cache: retain (loaded once per animation frame) or cache (list)")
      ->delimiter(',')
      ->capture_default_str();
  app.add_option("--high-size", line.high_size, "High-level cache size (default: half the total)");
  app.add_option("--low-size", line.low_size, "Low-level cache size (default: the rest)");
  app.add_option("--high-assoc", line.high_assoc,
                 "High-level cache associativity under 'cache' (default: --assoc)");
  app.add_flag("--count-loads", line.count_loads,
               "retain: count the high-level loads as misses");
  app.add_option("--fetch", line.fetch,
                 "Fetch policy, Dinero IV's: demand, always, miss, tagged, load-forward, subblock. "
                 "Other than demand: --scheme single only, each configuration simulated by itself "
                 "(the stack groups that answer many configurations in one pass are demand-only); "
                 "misses are demand misses, as Dinero IV counts them")
      ->check(CLI::IsMember({"demand", "always", "miss", "tagged", "load-forward", "subblock"}))
      ->capture_default_str();
  app.add_option("--prefetch-distance", line.prefetch_distance,
                 "Blocks ahead that a prefetch goes (Dinero IV's -pfdist; load-forward and subblock: 1)")
      ->capture_default_str();
  app.add_flag("--tags-are-levels", line.tags_are_levels,
               "Read the tag field of a plain trace as the node level");
  if (side_tables) {
    app.add_option("--per-level", line.per_level,
                   "Write the table of references and misses per node level to FILE (its own table: "
                   "every configuration column, then level, refs, misses; - for standard output, "
                   "which then carries it alone)")
        ->type_name("FILE");
    app.add_option("--per-frame", line.per_animation_frame,
                   "Write the table of the counts of each animation frame (each with its own K) to "
                   "FILE (the main columns with frame after trace; - for standard output, which then "
                   "carries it alone)")
        ->type_name("FILE");
  }
  cli::add_format_option(app, line.format, "csv: one table, json: {\"columns\": [...], \"rows\": [...]}");
  app.add_option("--informat", line.informat,
                 "Record form of plain traces: din, xdin or binary (default: detected)")
      ->check(CLI::IsMember({"din", "xdin", "binary"}));
  app.add_option("--threads", line.threads, "Trace decoding threads (0: one per core; at most 16 per core)")
      ->capture_default_str();
}

template <typename T, typename Parse>
std::vector<T> parse_list(const std::vector<std::string>& texts, const char* option, Parse parse,
                          const char* accepted) {
  std::vector<T> values;
  for (const std::string& text : texts) {
    const auto value = parse(text);
    if (!value) {
      throw base::UsageError(fmt::format("{}: '{}' is not one of {}", option, text, accepted));
    }
    values.push_back(*value);
  }
  return values;
}

inline SweepOptions sweep_options(const RunCommandLine& line) {
  if (std::count(line.traces.begin(), line.traces.end(), "-") > 1) {
    throw base::UsageError("traces: standard input (-) is named more than once; it can be read only once");
  }
  SweepOptions options;
  options.sizes.clear();
  for (const auto& text : line.sizes) options.sizes.push_back(cache_size(text, "--size"));
  options.blocks.clear();
  for (const auto& text : line.blocks) {
    const std::uint64_t block = base::parse_byte_size(text, "--block");
    if (block > (1u << 30)) throw base::UsageError(fmt::format("--block {} is too large", text));
    check_power_of_two(block, text, "--block");
    options.blocks.push_back(static_cast<std::uint32_t>(block));
  }
  for (std::size_t i = 0; i < options.sizes.size(); ++i) {
    for (std::size_t b = 0; b < options.blocks.size(); ++b) {
      const std::uint64_t blocks = options.sizes[i] / options.blocks[b];
      if (blocks > kMaxCacheBlocks) {
        throw base::UsageError(fmt::format("--size {} with --block {}: {} blocks, at most {} in one cache "
                                              "(the simulator keeps each block's state)",
                                              line.sizes[i], line.blocks[b], blocks, kMaxCacheBlocks));
      }
    }
  }
  options.assocs.clear();
  for (const auto& text : line.assocs) options.assocs.push_back(assoc_option(text, "--assoc"));
  options.policies =
      parse_list<ReplacementPolicy>(line.policies, "--policy", parse_policy_name, kPolicyNames.data());
  options.schemes = parse_list<Scheme>(line.schemes, "--scheme", parse_scheme_name, "single, split");
  // A single cache is --size, and the split's halves are powers of two only
  // if --size is; with --high-size or --low-size the split's caches are
  // checked as such.
  const bool size_is_a_cache = std::find(options.schemes.begin(), options.schemes.end(), Scheme::Single) !=
                                   options.schemes.end() ||
                               (line.high_size.empty() && line.low_size.empty());
  for (std::size_t i = 0; i < options.sizes.size() && size_is_a_cache; ++i) {
    check_power_of_two(options.sizes[i], line.sizes[i], "--size");
  }
  options.high_policies =
      parse_list<HighPolicy>(line.high_policies, "--high-policy", parse_high_policy_name, "retain, cache");
  options.split_levels.clear();
  for (const auto& text : line.split_levels) {
    if (text == "auto") {
      options.split_levels.push_back(std::nullopt);
      continue;
    }
    std::uint32_t level = 0;
    const auto [next, error] = std::from_chars(text.data(), text.data() + text.size(), level);
    if (error != std::errc{} || next != text.data() + text.size() || level > formats::kMaxLevel) {
      throw base::UsageError(
          fmt::format("--split-level: '{}' is not a level: expected a number or 'auto'", text));
    }
    options.split_levels.push_back(level);
  }
  if (!line.high_size.empty()) options.high_size = cache_size(line.high_size, "--high-size");
  if (!line.low_size.empty()) options.low_size = cache_size(line.low_size, "--low-size");
  if (!line.high_assoc.empty()) options.high_assoc = assoc_option(line.high_assoc, "--high-assoc");
  options.count_loads = line.count_loads;
  options.fetch = parse_fetch_policy_name(line.fetch).value_or(FetchPolicy::Demand);
  options.prefetch_distance = line.prefetch_distance;
  options.per_level = !line.per_level.empty();
  options.per_animation_frame = !line.per_animation_frame.empty();
  if (line.per_level == "-" && line.per_animation_frame == "-") {
    throw base::UsageError(
        "--per-level - and --per-frame -: one table per output; write at least one of them to a file");
  }
  cli::check_distinct_outputs({{"--per-level", line.per_level},
                               {"--per-frame", line.per_animation_frame},
                               {"--per-unit", line.per_unit}});
  for (const std::string* file : {&line.per_level, &line.per_animation_frame, &line.per_unit}) {
    if (file->empty() || *file == "-") continue;
    for (const std::string& trace : line.traces) {
      if (trace != "-" && cli::same_output_file(trace, *file)) {
        throw base::UsageError(fmt::format("{}: named both as a trace{} and as a table to write", *file,
                                           trace == *file ? "" : fmt::format(" ('{}')", trace)));
      }
    }
    // Before the simulation, not after it.
    base::check_output_writable(*file);
  }
  return options;
}

// With --high-size and --low-size both given the split cache is their sum,
// whatever --size says: --size then sizes the single cache only. The note
// that says so where a --size given differs (nullopt: nothing to say).
inline std::optional<std::string> split_size_note(const RunCommandLine& line, const SweepOptions& options) {
  if (!options.high_size || !options.low_size || !line.sizes_given ||
      std::find(options.schemes.begin(), options.schemes.end(), Scheme::Split) == options.schemes.end()) {
    return std::nullopt;
  }
  const std::uint64_t total = *options.high_size + *options.low_size;
  if (std::all_of(options.sizes.begin(), options.sizes.end(), [&](std::uint64_t size) { return size == total; })) {
    return std::nullopt;
  }
  std::string sizes;
  for (const std::string& size : line.sizes) sizes += (sizes.empty() ? "" : ",") + size;
  return fmt::format("--size {} sizes the single cache only: the split cache is --high-size {} + --low-size {} "
                     "= {} bytes in all",
                     sizes, line.high_size, line.low_size, total);
}

inline formats::ReaderOptions reader_options(const RunCommandLine& line) {
  formats::ReaderOptions options;
  options.tags_are_levels = line.tags_are_levels;
  options.threads = cli::check_thread_count(line.threads, "--threads");
  if (!line.informat.empty()) options.form = formats::parse_form_name(line.informat);
  // Damage is caught by zstd's frame checksums and the content hash; the
  // record hash (a pass over all the text) is left to `tracetool verify`.
  options.check_record_hash = false;
  return options;
}

// What a run prints: `out` on standard output (or the file a caller
// chooses), `err` on standard error.
struct RunReport {
  std::string out, err;
};

// Notes go under a table, or on standard error so that CSV and JSON stay
// machine-readable.
inline void add_notes(RunReport& report, const std::vector<std::string>& notes, ReportFormat format) {
  for (const std::string& note : notes) {
    (format == ReportFormat::Table ? report.out : report.err) += fmt::format("note: {}\n", note);
  }
}

// Writes the report: `out` to standard output, `err` to standard error.
inline void print_run_report(const RunReport& report) {
  std::fwrite(report.out.data(), 1, report.out.size(), stdout);
  std::fflush(stdout);
  std::fwrite(report.err.data(), 1, report.err.size(), stderr);
}

// The format of a side table's file: a name ending in .csv or .json says
// it (docs/guide/caches.md: --per-frame frames.csv), any other name and "-" take --format.
inline ReportFormat table_file_format(const std::string& path, ReportFormat format) {
  if (path.ends_with(".csv")) return ReportFormat::Csv;
  if (path.ends_with(".json")) return ReportFormat::Json;
  return format;
}

// Writes one table to `path` ("-": the report's own output), whole or not at all.
inline void write_table(const std::string& path, const std::string& text, RunReport& report) {
  if (path == "-") {
    report.out += text;
    return;
  }
  base::OutputFile file(path);
  file.write(text);
  file.commit();
}

// The report and its notes. Each table is an output of its own: the main
// one in `out`, unless --per-level - or --per-frame - puts that table there
// instead; the others in their files.
inline RunReport run_report(const std::vector<ResultRow>& rows, const std::vector<LevelRow>& levels,
                            const std::vector<std::string>& notes, const RunCommandLine& line,
                            const std::vector<AnimationFrameRow>& frames = {},
                            const std::vector<UnitRow>& unit_rows = {}) {
  RunReport report;
  const ReportFormat format = parse_report_format(line.format).value_or(ReportFormat::Table);
  if (!line.per_level.empty()) {
    write_table(line.per_level, format_level_rows(levels, table_file_format(line.per_level, format)), report);
  }
  if (!line.per_animation_frame.empty()) {
    write_table(line.per_animation_frame,
                format_animation_frame_rows(frames, table_file_format(line.per_animation_frame, format)), report);
  }
  if (!line.per_unit.empty()) {
    write_table(line.per_unit, format_unit_rows(unit_rows, table_file_format(line.per_unit, format)), report);
  }
  if (line.per_level != "-" && line.per_animation_frame != "-" && line.per_unit != "-") {
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

}  // namespace nodetrace::cachesim::tools
