// The report of `cachesim run` and `dinero-wrap run`: one row per trace and
// configuration, columns of docs/ARCHITECTURE.md "Report columns", as an
// aligned table (for people), CSV with a header line, or JSON. Every output is
// one table: CSV one header and rows of its width; JSON always the object
// {"columns": [names], "rows": [{column: value}, ...]} (numbers as numbers,
// empty columns as null). The per-level, per-frame and per-unit tables are
// outputs of their own (`--per-level FILE`, `--per-frame FILE`, `--per-unit
// FILE`), never appended to the main one.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "nodetrace/cachesim/sampling/sampled_sweep.hpp"
#include "nodetrace/cachesim/report/result_row.hpp"

namespace nodetrace::cachesim {

enum class ReportFormat : std::uint8_t { Table, Csv, Json };
std::optional<ReportFormat> parse_report_format(std::string_view name);

// The column names, in order.
const std::vector<std::string>& report_columns();
// The configuration columns (trace .. split_level) lead every table.
inline constexpr std::size_t kConfigurationColumns = 10;
// Per-level: the configuration columns, then level, refs, misses.
const std::vector<std::string>& level_report_columns();
const std::vector<std::string>& animation_frame_report_columns();  // the main ones, `frame` after `trace`
const std::vector<std::string>& unit_report_columns();  // the main ones, `unit` after `trace`

// misses / fetches with six decimals, rounded half up, from integer counts
// (empty when there are no fetches: a ratio of nothing is not 0).
std::string miss_ratio_text(std::uint64_t misses, std::uint64_t fetches);

// The assoc column: the ways, or `full` when the (low) cache is one set.
std::string assoc_text(const Configuration& config);

// The cells of one row (empty strings for empty columns).
std::vector<std::string> report_cells(const ResultRow& row);
std::vector<std::string> level_report_cells(const LevelRow& row);
std::vector<std::string> animation_frame_report_cells(const AnimationFrameRow& row);
std::vector<std::string> unit_report_cells(const UnitRow& row);

// Any table of text cells in `format` (the shapes above); `text_column(c)`
// says which columns JSON quotes (others are numbers unless a cell is not one).
std::string format_cells(const std::vector<std::string>& columns,
                         const std::vector<std::vector<std::string>>& rows, ReportFormat format,
                         bool (*text_column)(std::size_t));

// Runs with a second-level cache (`--l2-size`) append these after
// low_misses, in every row: its geometry, the first-level fetches it saw,
// its fetches, misses and miss ratio (six decimals, empty without fetches).
const std::vector<std::string>& second_level_columns();
// Runs with --prefetch (docs/guide/caches.md) append these last, in every
// row: the prefetcher (none, treelet[:BYTES], treelet-low[:BYTES]), its
// prefetches, the useful ones, accuracy (useful / prefetches), the misses of
// the same configuration without it, coverage ((those - misses) / those,
// signed), and bytes fetched per ray (empty when the trace has no ray count).
const std::vector<std::string>& prefetch_columns();
// The main table alone (with the second-level or prefetch columns when its rows have them).
std::string format_rows(const std::vector<ResultRow>& rows, ReportFormat format);
// The per-level table alone.
std::string format_level_rows(const std::vector<LevelRow>& rows, ReportFormat format);
// The per-frame table alone.
std::string format_animation_frame_rows(const std::vector<AnimationFrameRow>& rows, ReportFormat format);
// The per-unit table alone (`cachesim run --units private --per-unit FILE`).
std::string format_unit_rows(const std::vector<UnitRow>& rows, ReportFormat format);

// Sampled runs (docs/ARCHITECTURE.md "Report columns", cachesim/SAMPLING.md): the main
// columns, then these, in every row; then one `gain` row per split
// configuration that has a single one of the same size, block, assoc and
// policy: the split row's configuration columns, its refs and fetches, an
// empty misses column, miss_ratio = single minus split (signed, six
// decimals), empty high / low columns, then the gain's sampling columns.
const std::vector<std::string>& sampling_columns();
// The main columns and the sampling ones.
const std::vector<std::string>& sampled_report_columns();
std::vector<std::string> sampled_report_cells(const SampledRow& row);
std::vector<std::string> gain_report_cells(const GainRow& row);
// single minus split miss ratio, exact from the counts, rounded half away
// from zero to six decimals ("-0.012345").
std::string gain_text(const ResultRow& single, const ResultRow& split);
std::string format_sampled_report(const std::vector<SampledRow>& rows,
                                  const std::vector<GainRow>& gains, ReportFormat format);

}  // namespace nodetrace::cachesim
