#include "nodetrace/cachesim/report/report.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>

namespace nodetrace::cachesim {

std::optional<ReportFormat> parse_report_format(std::string_view name) {
  if (name == "table") return ReportFormat::Table;
  if (name == "csv") return ReportFormat::Csv;
  if (name == "json") return ReportFormat::Json;
  return std::nullopt;
}

const std::vector<std::string>& report_columns() {
  static const std::vector<std::string> columns{
      "trace",     "scheme",   "size",       "block",      "assoc",      "policy",
      "high_policy", "high_size", "low_size", "split_level", "refs",      "fetches",
      "misses",    "miss_ratio", "high_refs", "high_misses", "high_loads", "low_refs",
      "low_misses"};
  return columns;
}

const std::vector<std::string>& level_report_columns() {
  static const std::vector<std::string> columns = [] {
    std::vector<std::string> all(report_columns().begin(), report_columns().begin() + kConfigurationColumns);
    all.insert(all.end(), {"level", "refs", "misses"});
    return all;
  }();
  return columns;
}

namespace {

// The main columns with `key` (a per-frame or per-unit table's) after `trace`.
std::vector<std::string> keyed_columns(const char* key) {
  std::vector<std::string> columns = report_columns();
  columns.insert(columns.begin() + 1, key);
  return columns;
}

}  // namespace

const std::vector<std::string>& animation_frame_report_columns() {
  static const std::vector<std::string> columns = keyed_columns("frame");
  return columns;
}

const std::vector<std::string>& unit_report_columns() {
  static const std::vector<std::string> columns = keyed_columns("unit");
  return columns;
}

std::string miss_ratio_text(std::uint64_t misses, std::uint64_t fetches) {
  if (fetches == 0) return {};
  // Rounded half up: floor((2 * 10^6 * misses + fetches) / (2 * fetches)).
  const unsigned __int128 scaled =
      (static_cast<unsigned __int128>(misses) * 2000000u + fetches) /
      (static_cast<unsigned __int128>(fetches) * 2u);
  const auto whole = static_cast<std::uint64_t>(scaled / 1000000u);
  const auto fraction = static_cast<std::uint64_t>(scaled % 1000000u);
  return fmt::format("{}.{:06}", whole, fraction);
}

namespace {

// Which columns are text (quoted in JSON); the others are numbers.
bool is_text_column(std::size_t column) {
  return column == 0 || column == 1 || column == 5 || column == 6;
}

bool is_number(const std::string& cell) {
  return !cell.empty() && cell.find_first_not_of("0123456789.-") == std::string::npos;
}

std::string csv_field(const std::string& cell) {
  if (cell.find_first_of(",\"\n\r") == std::string::npos) return cell;
  std::string quoted = "\"";
  for (const char c : cell) {
    if (c == '"') quoted += '"';
    quoted += c;
  }
  quoted += '"';
  return quoted;
}

}  // namespace

std::string format_cells(const std::vector<std::string>& columns,
                         const std::vector<std::vector<std::string>>& rows, ReportFormat format,
                         bool (*text_column)(std::size_t)) {
  std::string out;
  switch (format) {
    case ReportFormat::Csv: {
      for (std::size_t c = 0; c < columns.size(); ++c) {
        if (c) out += ',';
        out += columns[c];
      }
      out += '\n';
      for (const auto& row : rows) {
        for (std::size_t c = 0; c < row.size(); ++c) {
          if (c) out += ',';
          out += csv_field(row[c]);
        }
        out += '\n';
      }
      return out;
    }
    case ReportFormat::Json: {
      // One shape whatever the options: {"columns": [...], "rows": [{...}, ...]}.
      out += "{\"columns\": [";
      for (std::size_t c = 0; c < columns.size(); ++c) {
        if (c) out += ", ";
        out += nlohmann::json(columns[c]).dump();
      }
      out += "],\n \"rows\": [";
      for (std::size_t r = 0; r < rows.size(); ++r) {
        out += r ? ",\n  {" : "\n  {";
        for (std::size_t c = 0; c < columns.size(); ++c) {
          if (c) out += ", ";
          out += nlohmann::json(columns[c]).dump();
          out += ": ";
          const std::string& cell = rows[r][c];
          if (cell.empty() && c != 0) {
            out += "null";
          } else if (text_column(c) || !is_number(cell)) {  // assoc may read `full`
            out += nlohmann::json(cell).dump();
          } else {
            out += cell;
          }
        }
        out += "}";
      }
      out += rows.empty() ? "]}\n" : "\n]}\n";
      return out;
    }
    case ReportFormat::Table: {
      std::vector<std::size_t> widths(columns.size());
      for (std::size_t c = 0; c < columns.size(); ++c) widths[c] = columns[c].size();
      for (const auto& row : rows) {
        for (std::size_t c = 0; c < row.size(); ++c) {
          widths[c] = std::max(widths[c], std::max<std::size_t>(row[c].size(), 1));
        }
      }
      auto append_line = [&](const std::vector<std::string>& cells, bool header) {
        std::string line;
        for (std::size_t c = 0; c < cells.size(); ++c) {
          if (c) line += "  ";
          const std::string cell = cells[c].empty() && !header ? "-" : cells[c];
          // Text left-aligned, numbers right-aligned.
          if (text_column(c)) {
            line += cell;
            if (c + 1 < cells.size()) line.append(widths[c] - cell.size(), ' ');
          } else {
            line.append(widths[c] - cell.size(), ' ');
            line += cell;
          }
        }
        out += line;
        out += '\n';
      };
      append_line(columns, true);
      for (const auto& row : rows) append_line(row, false);
      return out;
    }
  }
  return out;
}

namespace {

bool is_level_text_column(std::size_t column) { return is_text_column(column); }

// The main table's text columns, one place further after `frame` or `unit`.
bool is_keyed_text_column(std::size_t column) {
  return column == 0 || (column > 1 && is_text_column(column - 1));
}

}  // namespace

std::vector<std::string> report_cells(const ResultRow& row) {
  const Configuration& config = row.config;
  const bool split = config.scheme == Scheme::Split;
  auto number = [](std::uint64_t value) { return std::to_string(value); };
  auto split_number = [&](std::uint64_t value) { return split ? number(value) : std::string(); };
  return {
      row.trace,
      std::string(scheme_name(config.scheme)),
      number(config.size),
      number(config.block),
      assoc_text(config),
      std::string(policy_name(config.policy)),
      split ? std::string(high_policy_name(config.high_policy)) : std::string(),
      split_number(config.high_size),
      split_number(config.low_size),
      split_number(row.split_level),
      number(row.refs),
      number(row.fetches),
      number(row.misses),
      miss_ratio_text(row.misses, row.fetches),
      split_number(row.high_refs),
      split_number(row.high_misses),
      split && row.high_loads ? number(*row.high_loads) : std::string(),
      split_number(row.low_refs),
      split_number(row.low_misses),
  };
}

std::string assoc_text(const Configuration& config) {
  const std::uint64_t cache = config.scheme == Scheme::Split ? config.low_size : config.size;
  const std::uint64_t blocks = config.block ? cache / config.block : 0;
  return blocks > 1 && config.assoc == blocks ? std::string("full") : std::to_string(config.assoc);
}

std::vector<std::string> level_report_cells(const LevelRow& row) {
  ResultRow totals;
  totals.trace = row.trace;
  totals.config = row.config;
  totals.split_level = row.split_level;
  std::vector<std::string> cells = report_cells(totals);
  cells.resize(kConfigurationColumns);
  cells.push_back(std::to_string(row.level));
  cells.push_back(std::to_string(row.refs));
  cells.push_back(std::to_string(row.misses));
  return cells;
}

std::vector<std::string> animation_frame_report_cells(const AnimationFrameRow& row) {
  std::vector<std::string> cells = report_cells(row.row);
  cells.insert(cells.begin() + 1, std::to_string(row.frame));
  return cells;
}

std::vector<std::string> unit_report_cells(const UnitRow& row) {
  std::vector<std::string> cells = report_cells(row.row);
  cells.insert(cells.begin() + 1, std::to_string(row.unit));
  return cells;
}

std::string format_unit_rows(const std::vector<UnitRow>& rows, ReportFormat format) {
  std::vector<std::vector<std::string>> cells;
  cells.reserve(rows.size());
  for (const UnitRow& row : rows) cells.push_back(unit_report_cells(row));
  return format_cells(unit_report_columns(), cells, format, is_keyed_text_column);
}

const std::vector<std::string>& second_level_columns() {
  static const std::vector<std::string> columns = {"l2_size",  "l2_block",  "l2_assoc",     "l2_refs",
                                                    "l2_fetches", "l2_misses", "l2_miss_ratio"};
  return columns;
}

const std::vector<std::string>& prefetch_columns() {
  static const std::vector<std::string> columns = {
      "prefetch",          "prefetches",        "useful_prefetches", "prefetch_accuracy", "misses_without_prefetch",
      "prefetch_coverage", "bytes_per_ray"};
  return columns;
}

std::vector<std::string> prefetch_cells(const ResultRow& row) {
  const PrefetchColumns prefetch = row.prefetch.value_or(PrefetchColumns{});
  const std::uint64_t base = prefetch.misses_without_prefetch;
  std::string coverage;
  if (base > 0) {
    const bool fewer = row.misses <= base;
    coverage = miss_ratio_text(fewer ? base - row.misses : row.misses - base, base);
    if (!fewer) coverage = "-" + coverage;
  }
  return {prefetch_name(prefetch.spec),
          std::to_string(prefetch.counts.prefetches),
          std::to_string(prefetch.counts.useful),
          miss_ratio_text(prefetch.counts.useful, prefetch.counts.prefetches),
          std::to_string(base),
          coverage,
          prefetch.rays ? miss_ratio_text(prefetch.fetched_blocks * row.config.block, *prefetch.rays) : std::string()};
}

std::string format_rows(const std::vector<ResultRow>& rows, ReportFormat format) {
  std::vector<std::vector<std::string>> cells;
  cells.reserve(rows.size());
  // A run with a second-level cache has its columns in every row; one with
  // --prefetch its prefetch columns after them.
  const bool second_level = !rows.empty() && rows.front().l2.has_value();
  const bool prefetch = !rows.empty() && rows.front().prefetch.has_value();
  for (const ResultRow& row : rows) {
    std::vector<std::string>& row_cells = cells.emplace_back(report_cells(row));
    if (prefetch && !second_level) {
      const std::vector<std::string> more = prefetch_cells(row);
      row_cells.insert(row_cells.end(), more.begin(), more.end());
    }
    if (!second_level) continue;
    const SecondLevelCounts l2 = row.l2.value_or(SecondLevelCounts{});
    for (const std::uint64_t value : {l2.size, std::uint64_t{l2.block}, std::uint64_t{l2.assoc}, l2.refs, l2.fetches,
                                      l2.misses}) {
      row_cells.push_back(std::to_string(value));
    }
    row_cells.push_back(miss_ratio_text(l2.misses, l2.fetches));
  }
  std::vector<std::string> columns = report_columns();
  if (prefetch && !second_level) columns.insert(columns.end(), prefetch_columns().begin(), prefetch_columns().end());
  if (!second_level) return format_cells(columns, cells, format, is_text_column);
  columns.insert(columns.end(), second_level_columns().begin(), second_level_columns().end());
  return format_cells(columns, cells, format, is_text_column);
}

std::string format_level_rows(const std::vector<LevelRow>& rows, ReportFormat format) {
  std::vector<std::vector<std::string>> cells;
  cells.reserve(rows.size());
  for (const LevelRow& row : rows) cells.push_back(level_report_cells(row));
  return format_cells(level_report_columns(), cells, format, is_level_text_column);
}

std::string format_animation_frame_rows(const std::vector<AnimationFrameRow>& rows, ReportFormat format) {
  std::vector<std::vector<std::string>> cells;
  cells.reserve(rows.size());
  for (const AnimationFrameRow& row : rows) cells.push_back(animation_frame_report_cells(row));
  return format_cells(animation_frame_report_columns(), cells, format, is_keyed_text_column);
}

const std::vector<std::string>& sampling_columns() {
  static const std::vector<std::string> columns{"sampled_fraction", "miss_ratio_se",
                                                "miss_ratio_low95", "miss_ratio_high95"};
  return columns;
}

const std::vector<std::string>& sampled_report_columns() {
  static const std::vector<std::string> columns = [] {
    std::vector<std::string> all = report_columns();
    all.insert(all.end(), sampling_columns().begin(), sampling_columns().end());
    return all;
  }();
  return columns;
}

namespace {

std::string decimal_text(const std::optional<double>& value) {
  if (!value) return {};
  const std::string text = fmt::format("{:.6f}", *value);
  return text == "-0.000000" ? "0.000000" : text;
}

void append_sampling_cells(std::vector<std::string>& cells, double fraction,
                           const Estimate& estimate) {
  cells.push_back(decimal_text(fraction));
  cells.push_back(decimal_text(estimate.standard_error));
  cells.push_back(decimal_text(estimate.low95));
  cells.push_back(decimal_text(estimate.high95));
}

}  // namespace

std::vector<std::string> sampled_report_cells(const SampledRow& row) {
  std::vector<std::string> cells = report_cells(row.row);
  append_sampling_cells(cells, row.sampled_fraction, row.estimate);
  return cells;
}

std::string gain_text(const ResultRow& single, const ResultRow& split) {
  // (m1 f2 - m2 f1) / (f1 f2); a side without fetches has ratio 0.
  using Wide = __int128;
  const Wide f1 = single.fetches ? Wide(single.fetches) : 1;
  const Wide f2 = split.fetches ? Wide(split.fetches) : 1;
  const Wide m1 = single.fetches ? Wide(single.misses) : 0;
  const Wide m2 = split.fetches ? Wide(split.misses) : 0;
  const Wide numerator = m1 * f2 - m2 * f1;
  const Wide denominator = f1 * f2;
  const bool negative = numerator < 0;
  const Wide magnitude = negative ? -numerator : numerator;
  const Wide scaled = (magnitude * 2000000 + denominator) / (denominator * 2);
  const auto whole = static_cast<std::uint64_t>(scaled / 1000000);
  const auto fraction = static_cast<std::uint64_t>(scaled % 1000000);
  return fmt::format("{}{}.{:06}", negative && scaled != 0 ? "-" : "", whole, fraction);
}

std::vector<std::string> gain_report_cells(const GainRow& row) {
  std::vector<std::string> cells = report_cells(row.split);
  cells[1] = "gain";
  cells[12].clear();  // misses
  cells[13] = gain_text(row.single, row.split);
  for (std::size_t c = 14; c < cells.size(); ++c) cells[c].clear();
  append_sampling_cells(cells, row.sampled_fraction, row.estimate);
  return cells;
}

std::string format_sampled_report(const std::vector<SampledRow>& rows,
                                  const std::vector<GainRow>& gains, ReportFormat format) {
  std::vector<std::vector<std::string>> cells;
  for (const SampledRow& row : rows) cells.push_back(sampled_report_cells(row));
  for (const GainRow& row : gains) cells.push_back(gain_report_cells(row));
  return format_cells(sampled_report_columns(), cells, format, is_text_column);
}

}  // namespace nodetrace::cachesim
