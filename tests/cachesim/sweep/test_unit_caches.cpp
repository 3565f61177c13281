// `cachesim run --units private` and `--l2-size` on a trace of 4 traversal
// units made by the tracer: each unit's private cache gives what Dinero IV
// (the real one where it is built, else `cachesim dinero`) gives on that
// unit's records (`tracetool cat --unit u`), the report's rows are the sums,
// and the second level gives what Dinero IV gives on a trace of the first
// level's fetches, made here by an independent first-level model.
#include <gtest/gtest.h>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>

#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "nodetrace/formats/read/trace_reader.hpp"
#include "test_support.hpp"

namespace nodetrace::cachesim {
namespace {

using nodetrace::testing::csv_rows;
using nodetrace::testing::program;
using nodetrace::testing::run_command;
using nodetrace::testing::shell_quoted;
using nodetrace::testing::TempDir;

constexpr unsigned kUnits = 4;
constexpr unsigned kSplitLevel = 4;

class UnitCaches : public ::testing::Test {
 protected:
  void SetUp() override {
    for (const char* name : {"tracer", "tracetool", "cachesim"}) {
      if (!std::filesystem::exists(program(name))) GTEST_SKIP() << name << " is not built";
    }
    const auto made = run_command(shell_quoted(program("tracer")) +
                                  " render mountain:6 --width 40 --height 30 -q --rays-in-flight 8 --units 4 "
                                  "--pixel-order tiled --unit-pixels 16 -o " + trace());
    ASSERT_EQ(made.exit_code, 0) << made.err;
  }
  std::string trace() const { return shell_quoted(dir_ / "u.din.zst"); }
  static std::string tool(const char* name) { return shell_quoted(program(name)); }
  // A CSV table as rows of column -> cell.
  static std::vector<std::map<std::string, std::string>> table(const std::string& csv) {
    return nodetrace::testing::csv_table(csv);
  }
  // Dinero IV's total demand misses of cache `cache` (e.g. "l1-ucache").
  static std::uint64_t dinero_misses(const std::string& output, const std::string& cache = "l1-ucache") {
    const auto at = output.find(" Demand Misses", output.find(cache));
    EXPECT_NE(at, std::string::npos) << output;
    return at == std::string::npos ? 0 : std::stoull(output.substr(at + 14));
  }
  // The real Dinero IV where it is built, else ours.
  static std::string dinero() {
    if (const auto real = nodetrace::testing::real_dinero()) return shell_quoted(*real);
    return tool("cachesim") + " dinero";
  }
  TempDir dir_;
};

TEST_F(UnitCaches, PrivateCachesPerUnitAreDineroIvOnThatUnitsRecordsAndTheReportSumsThem) {
  const auto run = run_command(tool("cachesim") + " run " + trace() +
                               " --units private --size 1k,4k --assoc 1,2 --scheme single,split --split-level " +
                               std::to_string(kSplitLevel) + " --format csv --per-unit " +
                               shell_quoted(dir_ / "units.csv"));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const auto totals = table(run.out);
  const auto units = table(nodetrace::testing::read_file(dir_ / "units.csv"));
  ASSERT_EQ(totals.size(), 8u);
  ASSERT_EQ(units.size(), 8u * kUnits);
  EXPECT_EQ(csv_rows(nodetrace::testing::read_file(dir_ / "units.csv")).at(0).at(1), "unit");
  for (unsigned u = 0; u < kUnits; ++u) {
    const std::string unit_trace = shell_quoted(dir_ / fmt::format("unit{}.din", u));
    ASSERT_EQ(run_command(tool("tracetool") + " cat --unit " + std::to_string(u) + " " + trace() + " > " + unit_trace)
                  .exit_code,
              0);
    // Each unit's rows against Dinero IV (single) and against a shared run
    // on that unit's records alone (split, which Dinero IV cannot do).
    const auto alone = table(run_command(tool("cachesim") + " run " + unit_trace +
                                         " --tags-are-levels --size 1k,4k --assoc 1,2 --scheme single,split "
                                         "--split-level " + std::to_string(kSplitLevel) + " --format csv")
                                 .out);
    ASSERT_EQ(alone.size(), 8u);
    for (std::size_t c = 0; c < 8; ++c) {
      const auto& row = units[u * 8 + c];
      ASSERT_EQ(row.at("unit"), std::to_string(u));
      for (const char* column : {"scheme", "size", "assoc", "refs", "fetches", "misses", "high_loads", "low_misses"}) {
        EXPECT_EQ(row.at(column), alone[c].at(column)) << "unit " << u << " row " << c << " " << column;
      }
      if (row.at("scheme") == "single") {
        const std::string size = row.at("size"), assoc = row.at("assoc");
        const auto out = run_command(dinero() + " -l1-usize " + size + " -l1-ubsize 8 -l1-uassoc " + assoc +
                                     " -informat d < " + unit_trace);
        ASSERT_EQ(out.exit_code, 0) << out.err;
        EXPECT_EQ(std::to_string(dinero_misses(out.out)), row.at("misses")) << "unit " << u << " " << size;
      }
    }
  }
  for (std::size_t c = 0; c < 8; ++c) {
    for (const char* column : {"refs", "fetches", "misses", "low_misses"}) {
      std::uint64_t sum = 0;
      for (unsigned u = 0; u < kUnits; ++u) {
        const std::string& cell = units[u * 8 + c].at(column);
        sum += cell.empty() ? 0 : std::stoull(cell);
      }
      const std::string& total = totals[c].at(column);
      EXPECT_EQ(total.empty() ? 0 : std::stoull(total), sum) << c << " " << column;
    }
  }
}

// The first level's fetches, by an independent model: direct-mapped caches
// of 8-byte blocks (one per unit when private), a split scheme's levels < K
// in a high cache that keeps every block of the (one) animation frame, as
// `r ADDRESS 8` lines: what the second level must see.
std::string first_level_fetches(const std::vector<formats::Record>& records, std::uint64_t size, bool split,
                                bool private_units) {
  const std::uint64_t low_blocks = (split ? size / 2 : size) / 8;
  std::vector<std::vector<std::uint64_t>> low(private_units ? kUnits : 1,
                                               std::vector<std::uint64_t>(low_blocks, ~std::uint64_t{0}));
  std::vector<std::map<std::uint64_t, bool>> high(private_units ? kUnits : 1);
  std::ostringstream out;
  for (const formats::Record& record : records) {
    const std::uint64_t block = record.address >> 3;
    const unsigned unit = private_units ? formats::unit_index(record.unit) : 0;
    bool fetched;
    if (split && record.tag < kSplitLevel) {
      fetched = high[unit].emplace(block, true).second;
    } else {
      std::uint64_t& slot = low[unit][block % low_blocks];
      fetched = slot != block;
      slot = block;
    }
    if (fetched) out << fmt::format("r {:x} 8\n", block << 3);
  }
  return out.str();
}

TEST_F(UnitCaches, SecondLevelIsDineroIvOnTheFirstLevelsFetches) {
  std::vector<formats::Record> records;
  {
    auto reader = formats::TraceReader::open((dir_ / "u.din.zst").string());
    formats::RecordBatch batch;
    while (reader->next(batch)) records.insert(records.end(), batch.records.begin(), batch.records.end());
  }
  for (const bool private_units : {false, true}) {
    const auto run = run_command(tool("cachesim") + " run " + trace() + " --units " +
                                 (private_units ? "private" : "shared") +
                                 " --size 1k --scheme single,split --split-level " + std::to_string(kSplitLevel) +
                                 " --l2-size 4k --l2-block 32 --l2-assoc 2 --format csv");
    ASSERT_EQ(run.exit_code, 0) << run.err;
    const auto rows = table(run.out);
    ASSERT_EQ(rows.size(), 2u);
    for (const auto& row : rows) {
      const bool split = row.at("scheme") == "split";
      const std::string fetches = first_level_fetches(records, 1024, split, private_units);
      const auto path = dir_ / "l1-fetches.xdin";
      nodetrace::testing::write_file(path, fetches);
      const auto out = run_command(dinero() + " -l1-usize 4k -l1-ubsize 32 -l1-uassoc 2 -informat D < " +
                                   shell_quoted(path));
      ASSERT_EQ(out.exit_code, 0) << out.err;
      const auto lines = static_cast<std::uint64_t>(std::count(fetches.begin(), fetches.end(), '\n'));
      EXPECT_EQ(row.at("l2_refs"), std::to_string(lines)) << row.at("scheme") << private_units;
      EXPECT_EQ(row.at("l2_misses"), std::to_string(dinero_misses(out.out))) << row.at("scheme") << private_units;
      EXPECT_EQ(row.at("l2_size"), "4096");
      EXPECT_FALSE(row.at("l2_miss_ratio").empty());
    }
  }
}

// DESIGN.md's shapes: the per-unit rows are a table of their own (`unit`
// after `trace`), and the L2 columns follow low_misses in every row, in CSV
// and JSON alike.
TEST_F(UnitCaches, PerUnitAndSecondLevelTablesHaveOneShape) {
  const std::string run = tool("cachesim") + " run " + trace() + " --size 1k --scheme single,split --split-level 4";
  const auto per_unit = run_command(run + " --units private --per-unit - --format json");
  ASSERT_EQ(per_unit.exit_code, 0) << per_unit.err;
  const auto units = nlohmann::json::parse(per_unit.out);
  ASSERT_EQ(units.at("columns").at(0), "trace");
  EXPECT_EQ(units.at("columns").at(1), "unit");
  ASSERT_EQ(units.at("rows").size(), 2u * kUnits);
  EXPECT_EQ(units.at("rows").at(3).at("unit"), 1);
  const auto l2 = run_command(run + " --l2-size 8k --format json");
  ASSERT_EQ(l2.exit_code, 0) << l2.err;
  const auto table = nlohmann::json::parse(l2.out);
  const auto& columns = table.at("columns");
  const auto low = std::find(columns.begin(), columns.end(), "low_misses");
  ASSERT_NE(low, columns.end());
  EXPECT_EQ(*(low + 1), "l2_size");
  EXPECT_EQ(columns.back(), "l2_miss_ratio");
  for (const auto& row : table.at("rows")) {
    EXPECT_EQ(row.size(), columns.size());
    EXPECT_TRUE(row.at("l2_miss_ratio").is_number());
  }
  const auto csv = run_command(run + " --units private --l2-size 8k --format csv");
  EXPECT_EQ(nodetrace::testing::one_csv_table(csv.out), "");
}

// Issue 52 item 9: plain text keeps each record's unit field but no header,
// so it reads as one unit. The conversion says so, and --units private on
// it is an error rather than the shared result under a private label (a
// container of one unit gets that result with a note).
TEST_F(UnitCaches, PlainConversionSaysUnitsAreLostAndPrivateCachesRefuseIt) {
  const std::string plain = shell_quoted(dir_ / "u.din");
  const auto converted = run_command(tool("tracetool") + " convert " + trace() + " " + plain);
  ASSERT_EQ(converted.exit_code, 0) << converted.err;
  EXPECT_NE(converted.err.find("lost its layout (K = auto needs it), its 4 traversal units (each line keeps its unit "
                               "field, but a trace without a header is read as one unit: cachesim --units private "
                               "needs them)"),
            std::string::npos)
      << converted.err;
  const auto kept = run_command(tool("tracetool") + " convert " + trace() + " " + shell_quoted(dir_ / "k.xdin.zst"));
  ASSERT_EQ(kept.exit_code, 0) << kept.err;
  EXPECT_EQ(kept.err.find("traversal units"), std::string::npos) << kept.err;
  const auto run = run_command(tool("cachesim") + " run " + plain + " --units private --size 1k");
  EXPECT_EQ(run.exit_code, 2) << run.out;
  EXPECT_EQ(run.out, "");
  EXPECT_NE(run.err.find("cachesim run: --units private: " + (dir_ / "u.din").string() +
                         ": a trace without a header is one traversal unit"),
            std::string::npos)
      << run.err;
  // A container whose header says one unit (a sweep over unit counts from
  // 1): the shared result, with a note that says why.
  const auto one = dir_ / "one.din.zst";
  ASSERT_EQ(run_command(tool("tracer") + " render mountain:6 --width 8 --height 6 -q -o " + shell_quoted(one)).exit_code, 0);
  const auto single = run_command(tool("cachesim") + " run " + shell_quoted(one) + " --units private --size 1k --format csv");
  EXPECT_EQ(single.exit_code, 0) << single.err;
  EXPECT_EQ(single.out, run_command(tool("cachesim") + " run " + shell_quoted(one) + " --size 1k --format csv").out);
  EXPECT_NE(single.err.find("one traversal unit (no \"units\" above 1 in its header): its private caches are the "
                            "shared ones"),
            std::string::npos)
      << single.err;
  // Shared caches read it as the one unit it is.
  EXPECT_EQ(run_command(tool("cachesim") + " run " + plain + " --size 1k").exit_code, 0);
}

// Each usage error exits 2 with the message that names its option.
TEST_F(UnitCaches, UsageErrorsNameTheirOption) {
  const std::string run = tool("cachesim") + " run " + trace();
  const std::pair<const char*, const char*> cases[] = {
      {" --per-unit -", "cachesim run: --per-unit: the rows of private caches need --units private"},
      {" --units mine", "cachesim run: --units: mine not in {shared,private}"},
      {" --units private --per-level -", "cachesim run: --units private: not with --per-level"},
      {" --l2-block 32", "cachesim run: --l2-block, --l2-assoc and --l2-policy describe the cache --l2-size adds"},
      {" --l2-size 4k --policy random", "cachesim run: --l2-size: the first level cannot be random"},
      {" --l2-size 3k", "cachesim run: second-level cache (--l2-size, --l2-block, --l2-assoc): size 3072 is not a "
                        "power of two"},
  };
  for (const auto& [options, message] : cases) {
    const auto result = run_command(run + options);
    EXPECT_EQ(result.exit_code, 2) << options;
    EXPECT_TRUE(result.err.starts_with(message)) << options << "\n" << result.err;
  }
}

}  // namespace
}  // namespace nodetrace::cachesim
