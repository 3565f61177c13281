// The report of `cachesim run` and `dinero-wrap run`: one row per trace and
// configuration, columns of docs/ARCHITECTURE.md "Cache model", as an aligned table (for
// people), CSV with a header line, or JSON (an array of objects; numbers as
// numbers, empty columns as null).
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
const std::vector<std::string>& level_report_columns();
const std::vector<std::string>& animation_frame_report_columns();  // the main ones, `frame` after `trace`

// misses / fetches with six decimals, rounded half up, from integer counts
// ("0.000000" when there are no fetches).
std::string miss_ratio_text(std::uint64_t misses, std::uint64_t fetches);

// The cells of one row (empty strings for empty columns).
std::vector<std::string> report_cells(const ResultRow& row);
std::vector<std::string> level_report_cells(const LevelRow& row);
std::vector<std::string> animation_frame_report_cells(const AnimationFrameRow& row);

// The main table alone.
std::string format_rows(const std::vector<ResultRow>& rows, ReportFormat format);
// The per-level table alone.
std::string format_level_rows(const std::vector<LevelRow>& rows, ReportFormat format);
// The per-frame table alone.
std::string format_animation_frame_rows(const std::vector<AnimationFrameRow>& rows, ReportFormat format);

// The whole report: the main table, then (when `per_level`) the per-level
// table, then (when `per_animation_frame`) the per-frame table, separated by a blank
// line in table and CSV form; in JSON an object {"results": [...], "levels":
// [...], "frames": [...]} of the tables asked for, or the main array alone.
// Notes are not included (front ends print them: under the table, or on
// standard error for CSV and JSON so that those stay machine-readable).
std::string format_report(const std::vector<ResultRow>& rows,
                          const std::vector<LevelRow>& level_rows, bool per_level,
                          ReportFormat format, const std::vector<AnimationFrameRow>& animation_frame_rows = {},
                          bool per_animation_frame = false);

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
