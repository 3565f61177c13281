// The checks of the configuration differential test (config_cases.hpp).
#include "config_cases.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <map>
#include <sstream>

#include "address_stream.hpp"
#include "config_case_lists.hpp"
#include "config_case_prefetch_checks.hpp"
#include "seeded_draw.hpp"
#include "test_support.hpp"

namespace nodetrace::testing {

namespace {

using Row = std::map<std::string, std::string>;

// A row as text, for messages.
std::string row_text(const Row& row) {
  std::string text;
  for (const auto& [column, value] : row) text += (text.empty() ? "" : " ") + column + "=" + value;
  return text;
}

// The counts a row must show for `config`, column by column.
std::map<std::string, std::string> expected_cells(const Config& config, const reference::Counts& counts) {
  std::map<std::string, std::string> cells;
  auto number = [](std::uint64_t v) { return std::to_string(v); };
  cells["refs"] = number(counts.refs);
  cells["fetches"] = number(counts.fetches);
  cells["misses"] = number(counts.misses);
  cells["high_refs"] = config.split ? number(counts.high_refs) : "";
  cells["high_misses"] = config.split ? number(counts.high_misses) : "";
  cells["high_loads"] = config.split && config.retain ? number(counts.high_loads) : "";
  cells["low_refs"] = config.split ? number(counts.low_refs) : "";
  cells["low_misses"] = config.split ? number(counts.low_misses) : "";
  cells["split_level"] = config.split ? number(counts.split_level) : "";
  if (config.l2) {
    cells["l2_refs"] = number(counts.l2_refs);
    cells["l2_fetches"] = number(counts.l2_fetches);
    cells["l2_misses"] = number(counts.l2_misses);
  }
  return cells;
}

std::string compare_cells(const std::map<std::string, std::string>& expected,
                          const std::map<std::string, std::string>& row) {
  std::string out;
  for (const auto& [column, value] : expected) {
    const auto found = row.find(column);
    const std::string got = found == row.end() ? "(no column)" : found->second;
    if (got != value) out += fmt::format(" {} {} (expected {})", column, got, value);
  }
  return out;
}

std::uint64_t cell(const std::map<std::string, std::string>& row, const std::string& column) {
  const auto found = row.find(column);
  if (found == row.end() || found->second.empty()) return 0;
  return std::stoull(found->second);
}

// The Dinero IV options of a single-scheme configuration.
std::vector<std::string> dinero_arguments(const Config& config) {
  const char* policies = "lfr";
  const char* fetches = "damtls";
  std::vector<std::string> args = {"-informat", "D", "-l1-usize", std::to_string(config.size), "-l1-ubsize",
                                   std::to_string(config.block), "-l1-uassoc", std::to_string(config.assoc),
                                   "-l1-urepl", std::string(1, policies[static_cast<int>(config.policy)]),
                                   "-l1-ufetch", std::string(1, fetches[static_cast<int>(config.fetch)])};
  if (config.fetch != Fetch::Demand) args.insert(args.end(), {"-l1-upfdist", std::to_string(config.prefetch_distance)});
  if (config.l2) {
    args.insert(args.end(), {"-l2-usize", std::to_string(config.l2->size), "-l2-ubsize",
                             std::to_string(config.l2->block), "-l2-uassoc", std::to_string(config.l2->assoc),
                             "-l2-urepl", config.l2->policy == Policy::Lru ? "l" : "f"});
  }
  return args;
}

// Dinero IV's total demand fetches and misses of the cache whose section
// `section` names (l1-ucache, l2-ucache).
std::optional<std::pair<std::uint64_t, std::uint64_t>> dinero_totals(const std::string& out,
                                                                     const std::string& section) {
  const auto at = out.find(section);
  if (at == std::string::npos) return std::nullopt;
  auto number_after = [&](const std::string& label) -> std::optional<std::uint64_t> {
    const auto line = out.find(label, at);
    if (line == std::string::npos) return std::nullopt;
    std::istringstream in(out.substr(line + label.size()));
    double value = 0;
    if (!(in >> value)) return std::nullopt;
    return static_cast<std::uint64_t>(value);
  };
  const auto fetches = number_after(" Demand Fetches");
  const auto misses = number_after(" Demand Misses");
  if (!fetches || !misses) return std::nullopt;
  return std::make_pair(*fetches, *misses);
}

}  // namespace

ConfigCaseResult check_config_case(const ConfigCase& c, const Programs& programs, const std::filesystem::path& work) {
  ConfigCaseResult result;
  const auto trace = work / c.trace_name;
  write_config_case_trace(c, trace);
  auto differ = [&](std::string what) { result.differences.push_back(std::move(what)); };
  auto run = [&](const std::string& name, const std::string& command, const std::string& input = {}) {
    const auto outcome = run_command(command, input);
    std::string shown;  // as run from the kept case's folder
    const std::string folder = work.string();
    std::size_t from = 0;
    for (auto at = command.find(folder); at != std::string::npos; at = command.find(folder, from)) {
      shown += command.substr(from, at - from) + ".";
      from = at + folder.size();
    }
    shown += command.substr(from);
    result.runs.push_back({name, shown, outcome.exit_code, outcome.out, outcome.err});
    return result.runs.back();
  };
  auto cachesim = [&](const std::string& name, const std::vector<std::string>& args) {
    std::string command = shell_quoted(programs.cachesim) + " run " + shell_quoted(trace);
    for (const auto& a : args) command += " " + a;
    return run(name, command);
  };

  std::vector<reference::Result> expected, without_prefetch;
  bool any_does_not_fit = false;
  for (const ListedConfig& one : c.configs) {
    expected.push_back(reference::simulate(c.facts, one.config));
    any_does_not_fit = any_does_not_fit || expected.back().high_levels_do_not_fit;
    Config without = one.config;
    without.prefetch = false;
    without_prefetch.push_back(one.config.prefetch ? reference::simulate(c.facts, without) : expected.back());
  }

  // The list.
  std::vector<std::string> list_args = c.list_args;
  const auto levels_file = work / "levels.csv", frames_file = work / "frames.csv";
  std::filesystem::remove(levels_file);
  std::filesystem::remove(frames_file);
  if (c.per_level) list_args.insert(list_args.end(), {"--per-level", shell_quoted(levels_file)});
  if (c.per_frame) list_args.insert(list_args.end(), {"--per-frame", shell_quoted(frames_file)});
  const KeptRun list = cachesim("list", list_args);
  std::vector<Row> list_table;
  // Levels that do not fit a retained high cache are a usage error (exit 2).
  if (list.status != (any_does_not_fit ? 2 : 0)) {
    differ(fmt::format("list run: exit {} (expected {}{}): {}", list.status, any_does_not_fit ? 2 : 0,
                       any_does_not_fit ? ", a retained high cache that its levels do not fit" : "",
                       list.err.substr(0, 300)));
  } else if (list.status == 0) {
    list_table = csv_table(list.out);
    if (list_table.size() != c.configs.size()) {
      differ(fmt::format("list run: {} rows for {} configurations", list_table.size(), c.configs.size()));
      list_table.clear();
    }
  }
  const bool list_rows = !list_table.empty();

  // The same list through the Python module's simulate(), on a sample of the cases.
  if (programs.python_module && list_rows && c.seed % programs.python_every == 0) {
    const auto list_csv = work / "list.csv";
    write_file(list_csv, list.out);
    std::string command = "PYTHONPATH=" + shell_quoted(*programs.python_module) + " /usr/bin/python3 " +
                          shell_quoted(std::filesystem::path(NODETRACE_SOURCE_DIR) / "tests" / "differential" /
                                       "python_simulate_check.py") +
                          " " + shell_quoted(list_csv) + " " + shell_quoted(trace);
    for (const auto& a : list_args) command += " " + a;
    const KeptRun python = run("python", command);
    if (python.status != 0) {
      differ(fmt::format("nodetrace.simulate() of the list: {}", python.err.substr(0, 300)));
    } else {
      result.python_rows += list_table.size();
    }
  }

  // Each configuration alone, and against the reference.
  std::vector<std::map<std::string, std::string>> alone_rows(c.configs.size());
  for (std::size_t i = 0; i < c.configs.size(); ++i) {
    const ListedConfig& one = c.configs[i];
    const bool fits = !expected[i].high_levels_do_not_fit;
    const KeptRun alone = cachesim(fmt::format("alone-{}", i), one.alone_args);
    if (alone.status != (fits ? 0 : 2)) {
      differ(fmt::format("{}: alone: exit {} (expected {}): {}", one.name, alone.status, fits ? 0 : 2,
                         alone.err.substr(0, 300)));
      continue;
    }
    if (!fits) continue;
    const std::vector<Row> alone_table = csv_table(alone.out);
    if (alone_table.size() != 1) {
      differ(fmt::format("{}: alone: {} rows", one.name, alone_table.size()));
      continue;
    }
    alone_rows[i] = alone_table[0];
    ++result.rows;
    const auto cells = expected_cells(one.config, expected[i].total);
    // A list with --prefetch treelet has the prefetch columns in every row;
    // a configuration without the prefetcher run alone (--prefetch none) has none.
    auto listed_cells = cells;
    auto alone_cells = cells;
    auto check_prefetch_columns = [&](const Row& row, const char* which) {
      ++result.properties;
      const std::string broken =
          prefetch_properties(one.config, expected[i].total, without_prefetch[i].total, c.rays, row);
      if (!broken.empty()) differ(fmt::format("{}: {}, the prefetch columns:{}", one.name, which, broken));
    };
    if (c.prefetch_columns) {
      const auto prefetch_cells = expected_prefetch_cells(one.config, expected[i].total, without_prefetch[i].total);
      listed_cells.insert(prefetch_cells.begin(), prefetch_cells.end());
      if (one.config.prefetch) {
        alone_cells.insert(prefetch_cells.begin(), prefetch_cells.end());
        check_prefetch_columns(alone_table[0], "alone");
      }
      if (list_rows) check_prefetch_columns(list_table[i], "in the list");
    }
    if (const auto d = compare_cells(alone_cells, alone_table[0]); !d.empty()) {
      differ(fmt::format("{}: alone differs from the reference:{}", one.name, d));
    }
    if (list_rows) {
      Row listed_as_alone;  // the list's row in the alone row's columns
      for (const auto& [column, value] : list_table[i]) {
        if (alone_table[0].count(column) != 0) listed_as_alone[column] = value;
      }
      if (listed_as_alone != alone_table[0]) {
        differ(fmt::format("{}: its row in the list differs from the row alone: {} against {}", one.name,
                           row_text(list_table[i]), row_text(alone_table[0])));
      }
      if (const auto d = compare_cells(listed_cells, list_table[i]); !d.empty()) {
        differ(fmt::format("{}: in the list, differs from the reference:{}", one.name, d));
      }
    }
  }

  // Dinero IV, where it can express the configuration.
  // Dinero IV keeps 32-bit addresses: compared where no reference or prefetch reaches 2^32.
  const bool l2_comparable = std::none_of(c.facts.records.begin(), c.facts.records.end(), [](const TraceRecord& r) {
    return r.type == 1 || r.type == 4 || r.type == 5;  // writes back, copies back, invalidates: not L2-visible alike
  });
  if (programs.dinero && !reaches_2_32(c.facts.records)) {
    std::string xdin;
    for (const TraceRecord& r : c.facts.records) {
      if (!r.other_stream) xdin += fmt::format("{} {:x} {:x}\n", kTypeLetters[r.type], r.address, r.size);
    }
    const auto dinero_trace = work / "dinero.xdin";
    write_file(dinero_trace, xdin);
    for (std::size_t i = 0; i < c.configs.size(); ++i) {
      const Config& config = c.configs[i].config;
      const bool expressible = !config.split && !config.prefetch &&
                               (config.policy == Policy::Lru || config.policy == Policy::Fifo ||
                                config.policy == Policy::Random) &&
                               (!config.private_units || c.facts.units == 1);
      if (!expressible || alone_rows[i].empty()) continue;
      std::string command = "timeout 10 " + shell_quoted(*programs.dinero);
      for (const auto& a : dinero_arguments(config)) command += " " + a;
      const KeptRun real = run(fmt::format("dinero-{}", i), command + " < " + shell_quoted(dinero_trace));
      const auto l1 = dinero_totals(real.out, "l1-ucache");
      if (real.status != 0 || !l1) {
        differ(fmt::format("{}: Dinero IV failed (exit {}): {}", c.configs[i].name, real.status, real.err.substr(0, 200)));
        continue;
      }
      ++result.dinero_rows;
      const auto& row = alone_rows[i];
      if (cell(row, "fetches") != l1->first || cell(row, "misses") != l1->second) {
        differ(fmt::format("{}: Dinero IV counts {} fetches, {} misses; cachesim {}, {}", c.configs[i].name, l1->first,
                           l1->second, cell(row, "fetches"), cell(row, "misses")));
      }
      if (config.l2 && l2_comparable) {
        const auto l2 = dinero_totals(real.out, "l2-ucache");
        if (!l2 || cell(row, "l2_fetches") != l2->first || cell(row, "l2_misses") != l2->second) {
          differ(fmt::format("{}: Dinero IV's second level counts {} fetches, {} misses; cachesim {}, {}",
                             c.configs[i].name, l2 ? l2->first : 0, l2 ? l2->second : 0, cell(row, "l2_fetches"),
                             cell(row, "l2_misses")));
        }
      }
    }
  }

  // Properties of the rows the runs printed.
  auto same_geometry = [](const Config& a, const Config& b) {
    return a.split == b.split && a.size == b.size && a.block == b.block && a.assoc == b.assoc &&
           a.retain == b.retain && a.high_size == b.high_size && a.low_size == b.low_size &&
           a.high_assoc == b.high_assoc && a.split_level == b.split_level;
  };
  for (const auto* rows : {&list_table, &alone_rows}) {
    if (rows->size() != c.configs.size()) continue;
    const char* which = rows == &alone_rows ? "alone" : "in the list";
    for (std::size_t i = 0; i < c.configs.size(); ++i) {
      if (c.configs[i].config.policy != Policy::Opt || (*rows)[i].empty()) continue;
      for (std::size_t j = 0; j < c.configs.size(); ++j) {
        if (j == i || (*rows)[j].empty() || !same_geometry(c.configs[i].config, c.configs[j].config)) continue;
        ++result.properties;
        if (cell((*rows)[i], "misses") > cell((*rows)[j], "misses")) {
          differ(fmt::format("OPT is not a bound ({}): {} misses {} > {} misses {}", which, c.configs[i].name,
                             cell((*rows)[i], "misses"), c.configs[j].name, cell((*rows)[j], "misses")));
        }
      }
    }
    // A fully associative LRU cache misses no more when it grows.
    for (std::size_t i = 0; i < c.configs.size(); ++i) {
      for (std::size_t j = 0; j < c.configs.size(); ++j) {
        const Config& a = c.configs[i].config;
        const Config& b = c.configs[j].config;
        if ((*rows)[i].empty() || (*rows)[j].empty() || a.split || b.split || a.policy != Policy::Lru ||
            b.policy != Policy::Lru || a.fetch != Fetch::Demand || a.prefetch || b.prefetch || a.block != b.block ||
            a.size >= b.size ||
            a.assoc != a.size / a.block || b.assoc != b.size / b.block) {
          continue;
        }
        ++result.properties;
        if (cell((*rows)[j], "misses") > cell((*rows)[i], "misses")) {
          differ(fmt::format("fully associative LRU misses more when it grows ({}): {} {} against {} {}", which,
                             c.configs[j].name, cell((*rows)[j], "misses"), c.configs[i].name,
                             cell((*rows)[i], "misses")));
        }
      }
    }
  }

  // The per-level and per-frame tables: each configuration's rows sum to
  // its totals and equal the reference's.
  auto config_key = [](const std::map<std::string, std::string>& row, bool with_k) {
    std::string key;
    for (const char* column : {"scheme", "size", "block", "assoc", "policy", "high_policy", "high_size", "low_size"}) {
      key += row.count(column) ? row.at(column) + "|" : "|";
    }
    if (with_k && row.count("split_level")) key += row.at("split_level");
    return key;
  };
  if (list_rows && c.per_level) {
    const std::vector<Row> levels = csv_table(read_file(levels_file));
    std::map<std::string, std::vector<std::size_t>> configs_of;
    for (std::size_t i = 0; i < c.configs.size(); ++i) configs_of[config_key(list_table[i], true)].push_back(i);
    std::map<std::size_t, std::map<std::uint32_t, reference::LevelCounts>> got;
    for (const auto& row : levels) {
      const auto found = configs_of.find(config_key(row, true));
      if (found == configs_of.end()) {
        differ(fmt::format("per-level table: a row of no configuration of the list ({})", config_key(row, true)));
        continue;
      }
      if (found->second.size() != 1) continue;  // two configurations print alike: not told apart
      auto& counts = got[found->second[0]][static_cast<std::uint32_t>(cell(row, "level"))];
      counts.refs += cell(row, "refs");
      counts.misses += cell(row, "misses");
    }
    for (const auto& [i, by_level] : got) {
      std::uint64_t refs = 0, misses = 0;
      for (const auto& [level, counts] : by_level) {
        refs += counts.refs;
        misses += counts.misses;
        const auto want = expected[i].levels.count(level) ? expected[i].levels.at(level) : reference::LevelCounts{};
        if (counts.refs != want.refs || counts.misses != want.misses) {
          differ(fmt::format("{}: per-level table, level {}: {} refs, {} misses; the reference {}, {}",
                             c.configs[i].name, level, counts.refs, counts.misses, want.refs, want.misses));
        }
      }
      ++result.properties;
      // Untagged records have no level row: the table sums to the tagged records' totals.
      if (refs != cell(list_table[i], "refs") || misses != cell(list_table[i], "misses")) {
        differ(fmt::format("{}: per-level table sums to {} refs, {} misses; the totals are {}, {}", c.configs[i].name,
                           refs, misses, cell(list_table[i], "refs"), cell(list_table[i], "misses")));
      }
    }
  }
  if (list_rows && c.per_frame) {
    const std::vector<Row> frames = csv_table(read_file(frames_file));
    std::map<std::string, std::vector<std::size_t>> configs_of;
    for (std::size_t i = 0; i < c.configs.size(); ++i) configs_of[config_key(list_table[i], false)].push_back(i);
    std::map<std::size_t, std::vector<std::map<std::string, std::string>>> got;
    for (const auto& row : frames) {
      const auto found = configs_of.find(config_key(row, false));
      if (found == configs_of.end()) {
        differ(fmt::format("per-frame table: a row of no configuration of the list ({})", config_key(row, false)));
        continue;
      }
      if (found->second.size() == 1) got[found->second[0]].push_back(row);
    }
    const char* summed[] = {"refs", "fetches", "misses", "high_refs", "high_misses", "high_loads", "low_refs",
                            "low_misses"};
    for (const auto& [i, rows] : got) {
      std::map<std::string, std::uint64_t> sums;
      for (const auto& row : rows) {
        const std::uint64_t frame = cell(row, "frame");
        if (frame >= expected[i].frames.size()) {
          differ(fmt::format("{}: per-frame table: frame {} of {}", c.configs[i].name, frame, expected[i].frames.size()));
          continue;
        }
        if (const auto d = compare_cells(expected_cells(c.configs[i].config, expected[i].frames[frame]), row);
            !d.empty()) {
          differ(fmt::format("{}: per-frame table, frame {}, differs from the reference:{}", c.configs[i].name, frame, d));
        }
        for (const char* column : summed) sums[column] += cell(row, column);
      }
      ++result.properties;
      for (const char* column : summed) {
        if (sums[column] != cell(list_table[i], column)) {
          differ(fmt::format("{}: per-frame table's {} sum to {}; the total is {}", c.configs[i].name, column,
                             sums[column], cell(list_table[i], column)));
        }
      }
    }
  }

  // A curve's points (up to 16k) against the reference.
  if (!c.curve_args.empty()) {
    const KeptRun curve = cachesim("curve", c.curve_args);
    ++result.properties;
    if (curve.status != 0) {
      differ(fmt::format("--curve: exit {}: {}", curve.status, curve.err.substr(0, 300)));
    }
    for (const Row& point : curve.status == 0 ? csv_table(curve.out) : std::vector<Row>{}) {
      Config config;
      config.size = cell(point, "size");
      config.block = cell(point, "block");
      // The reference searches a set way by way: points of up to 1,024 blocks, 256 ways.
      if (config.size > 16384 || config.size < config.block || config.size / config.block > 1024) continue;
      config.assoc = point.at("assoc") == "full" ? static_cast<std::uint32_t>(config.size / config.block)
                                                  : static_cast<std::uint32_t>(cell(point, "assoc"));
      if (config.assoc > 256) continue;
      if (config.size / config.block < config.assoc) continue;
      config.policy = *reference::policy_named(point.at("policy"));
      const reference::Counts want = reference::simulate(c.facts, config).total;
      ++result.curve_points;
      if (cell(point, "fetches") != want.fetches || cell(point, "misses") != want.misses) {
        differ(fmt::format("--curve: {} at {} bytes, block {}, assoc {}: {} fetches, {} misses; the reference {}, {}",
                           point.at("policy"), config.size, config.block, point.at("assoc"), cell(point, "fetches"),
                           cell(point, "misses"), want.fetches, want.misses));
      }
    }
  }

  // Sampling at 1/1 is the full run.
  if (list_rows && c.sampling_allowed) {
    const bool sets = c.sample_sets;
    std::vector<std::size_t> kept;
    std::vector<std::string> policies;
    for (std::size_t i = 0; i < c.configs.size(); ++i) {
      const Policy p = c.configs[i].config.policy;
      if (p == Policy::Opt || (sets && (p == Policy::Brrip || p == Policy::Drrip))) continue;
      if (sets && p == Policy::Random) continue;  // refused with --sample-sets (once defect i)
      kept.push_back(i);
    }
    std::vector<std::string> args = c.list_args;
    const auto policy_at = std::find(args.begin(), args.end(), "--policy") + 1;
    for (const auto& p : [&] {
           std::vector<std::string> names;
           std::istringstream in(*policy_at);
           for (std::string name; std::getline(in, name, ',');) {
             if (name == "opt" || (sets && (name == "brrip" || name == "drrip"))) continue;
             if (!(sets && name == "random")) names.push_back(name);
           }
           return names;
         }()) {
      policies.push_back(p);
    }
    const bool one_block = std::count(args.begin(), args.end(), "--block") == 1 &&
                           (std::find(args.begin(), args.end(), "--block") + 1)->find(',') == std::string::npos;
    if (!policies.empty() && !kept.empty() && (!sets || one_block)) {
      *policy_at = join(policies);
      if (sets) {
        args.insert(args.end(), {"--sample-sets", "1/1"});
      } else {
        args.insert(args.end(), {"--sample-windows", "1/1", "--window-records", std::to_string(1 + c.seed % 500)});
      }
      const KeptRun sampled = cachesim("sampled", args);
      std::vector<std::map<std::string, std::string>> rows;
      for (const auto& row : csv_table(sampled.out)) {
        if (row.count("scheme") && row.at("scheme") != "gain") rows.push_back(row);
      }
      ++result.properties;
      if (sampled.status != 0 || rows.size() != kept.size()) {
        differ(fmt::format("sampled at 1/1: exit {}, {} rows for {} configurations: {}", sampled.status, rows.size(),
                           kept.size(), sampled.err.substr(0, 200)));
      } else {
        (sets ? result.sampled_sets : result.sampled_windows) += kept.size();
        for (std::size_t r = 0; r < kept.size(); ++r) {
          for (const char* column : {"refs", "fetches", "misses", "high_refs", "high_misses", "high_loads",
                                     "low_refs", "low_misses", "split_level"}) {
            const auto& full = list_table[kept[r]];
            const std::string want = full.count(column) ? full.at(column) : "";
            const std::string got = rows[r].count(column) ? rows[r].at(column) : "";
            if (want != got) {
              differ(fmt::format("{}: sampled at 1/1 ({}), {} {} against {} in the full run", c.configs[kept[r]].name,
                                 sets ? "sets" : "windows", column, got, want));
            }
          }
        }
      }
    }
  }
  return result;
}

ConfigCaseResult check_render_case(std::uint64_t seed, const Programs& programs, const std::filesystem::path& work) {
  ConfigCaseResult result;
  Draw draw(seed ^ 0x5EED0F4E4DE4ull);
  const std::array<const char*, 3> scenes = {"sphereflake:1", "mountain:6", "forest:1"};
  const std::array<const char*, 3> layouts = {"--layout dfl", "--layout bfl", "--layout hybrid --high-size 512"};
  ConfigCase c;  // what the list generator needs to know of the trace
  c.seed = seed;
  c.container = true;
  c.tagged = true;
  c.facts.units = draw.chance(30) ? 2 : 1;
  c.facts.nodes_per_level = {{1}};  // markers with level counts: K auto is allowed
  const Lists lists = make_lists(draw, c, ConfigCaseOptions{}, false);
  const std::string list = join(arguments(lists, texts(lists.sizes), texts(lists.blocks), assoc_texts(lists.assocs),
                                          lists.policies, lists.schemes, lists.split_levels, lists.high_policies),
                                " ");
  const auto trace = work / "render.din.zst", report = work / "render.csv";
  std::filesystem::remove(trace);
  std::filesystem::remove(report);
  const std::string render = fmt::format(
      "{} render {} --width 16 --height 12 --quiet {}{} -o {} --simulate '{}' --report {}",
      shell_quoted(*programs.tracer), draw.pick(scenes), draw.pick(layouts),
      c.facts.units > 1 ? " --rays-in-flight 4 --units 2" : "", shell_quoted(trace), list, shell_quoted(report));
  const auto rendered = run_command(render);
  result.runs.push_back({"render", render, rendered.exit_code, rendered.out, rendered.err});
  const std::string run = shell_quoted(programs.cachesim) + " run " + shell_quoted(trace) + " " + list;
  const auto simulated = run_command(run);
  result.runs.push_back({"cachesim", run, simulated.exit_code, simulated.out, simulated.err});
  ++result.properties;
  if (rendered.exit_code != 0 && !std::filesystem::exists(trace)) {
    // Refused before rendering (cachesim's own checks): nothing to compare with.
    if (rendered.exit_code != 2) result.differences.push_back(fmt::format("render: exit {}: {}", rendered.exit_code,
                                                                          rendered.err.substr(0, 300)));
    return result;
  }
  const std::string reported = read_file(report);
  if (simulated.exit_code == 0) result.rows = csv_table(simulated.out).size();
  if (rendered.exit_code != simulated.exit_code || (simulated.exit_code == 0 && reported != simulated.out)) {
    result.differences.push_back(fmt::format(
        "tracer render --simulate (exit {}) and cachesim run on its trace (exit {}) differ: {}", rendered.exit_code,
        simulated.exit_code, reported == simulated.out ? "(same report)" : "reports differ"));
  }
  return result;
}

void keep_runs(const ConfigCaseResult& result, const std::filesystem::path& folder, const std::string& header) {
  std::filesystem::create_directories(folder);
  for (const KeptRun& run : result.runs) {
    write_file(folder / (run.name + ".cmd"), run.command + "\n");
    write_file(folder / (run.name + ".out"), run.out);
    write_file(folder / (run.name + ".err"), run.err);
    write_file(folder / (run.name + ".status"), fmt::format("{}\n", run.status));
  }
  std::string text = header;
  for (const auto& d : result.differences) text += d + "\n";
  write_file(folder / "differences", text);
}

void keep_config_case(const ConfigCase& c, const ConfigCaseResult& result, const std::filesystem::path& folder) {
  std::string header = fmt::format("seed {}\n", c.seed);
  for (const auto& trigger : c.known_defect_triggers) header += "known-defect trigger: " + trigger + "\n";
  keep_runs(result, folder, header);
  write_config_case_trace(c, folder / c.trace_name);
  write_file(folder / "args", join(c.list_args, " ") + "\n");
}

}  // namespace nodetrace::testing