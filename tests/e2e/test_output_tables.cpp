// Every output a data-analysis user loads is one table (issue 22 items 1-2):
// each CSV output one header, the documented one, and rows of its width;
// each JSON output the object {"columns": [...], "rows": [...]} whose rows
// have exactly those keys, whatever the options. Per-level and per-frame
// tables are outputs of their own (--per-level FILE, --per-frame FILE).
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <set>
#include <string>
#include <vector>

#include "test_support.hpp"

namespace nodetrace::testing {
namespace {

// The documented headers (docs/ARCHITECTURE.md "Report columns", docs/guide/formats-and-outputs.md
// "Output shapes").
const std::vector<std::string> kConfiguration{"trace",       "scheme",    "size",     "block",      "assoc",
                                              "policy",      "high_policy", "high_size", "low_size", "split_level"};
std::vector<std::string> main_columns() {
  std::vector<std::string> columns = kConfiguration;
  columns.insert(columns.end(), {"refs", "fetches", "misses", "miss_ratio", "high_refs", "high_misses", "high_loads",
                                 "low_refs", "low_misses"});
  return columns;
}
std::vector<std::string> level_columns() {
  std::vector<std::string> columns = kConfiguration;
  columns.insert(columns.end(), {"level", "refs", "misses"});
  return columns;
}
std::vector<std::string> frame_columns() {
  std::vector<std::string> columns = main_columns();
  columns.insert(columns.begin() + 1, "frame");
  return columns;
}
std::vector<std::string> sampled_columns() {
  std::vector<std::string> columns = main_columns();
  columns.insert(columns.end(), {"sampled_fraction", "miss_ratio_se", "miss_ratio_low95", "miss_ratio_high95"});
  return columns;
}
const std::vector<std::string> kCurveColumns{"trace", "scheme", "block",   "assoc",  "policy",
                                             "split_level", "size", "fetches", "misses", "miss_ratio"};

void expect_json_table(const std::string& text, const std::vector<std::string>& columns, const std::string& what) {
  const auto json = nlohmann::json::parse(text);
  ASSERT_TRUE(json.is_object()) << what;
  ASSERT_EQ(json.size(), 2u) << what << ": " << text.substr(0, 200);
  EXPECT_EQ(json.at("columns").get<std::vector<std::string>>(), columns) << what;
  ASSERT_FALSE(json.at("rows").empty()) << what;
  for (const auto& row : json.at("rows")) {
    std::vector<std::string> keys;
    for (const auto& [key, value] : row.items()) keys.push_back(key);
    std::vector<std::string> sorted_columns = columns;
    std::sort(sorted_columns.begin(), sorted_columns.end());
    EXPECT_EQ(keys, sorted_columns) << what;  // nlohmann's items() are sorted by key
  }
}

class OutputTables : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir();
    trace_ = (dir_->path() / "t.din.zst").string();
    const auto render = run_command(shell_quoted(program("tracer")) +
                                    " render mountain:6 --width 16 --height 12 --quiet --layout hybrid "
                                    "--high-size 512 -o " + shell_quoted(trace_));
    ASSERT_EQ(render.exit_code, 0) << render.err;
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }
  static std::string cachesim(const std::string& arguments) {
    const auto result = run_command(shell_quoted(program("cachesim")) + " run " + shell_quoted(trace_) + " " +
                                    arguments);
    EXPECT_EQ(result.exit_code, 0) << arguments << ": " << result.err;
    return result.out;
  }
  static std::filesystem::path path(const std::string& name) { return dir_->path() / name; }

  static inline TempDir* dir_ = nullptr;
  static inline std::string trace_;
};

const std::string kConfigurations = "--size 1k,2k --assoc 1,4,full --scheme single,split --high-policy retain,cache";

TEST_F(OutputTables, CachesimRunCsvIsOneTableWithOrWithoutSideTables) {
  EXPECT_EQ(one_csv_table(cachesim(kConfigurations + " --format csv"), main_columns()), "");
  const std::string with_sides = cachesim(kConfigurations + " --per-level " + shell_quoted(path("l.csv")) +
                                          " --per-frame " + shell_quoted(path("f.csv")) + " --format csv");
  EXPECT_EQ(one_csv_table(with_sides, main_columns()), "");
  EXPECT_EQ(one_csv_table(read_file(path("l.csv")), level_columns()), "");
  EXPECT_EQ(one_csv_table(read_file(path("f.csv")), frame_columns()), "");
  EXPECT_EQ(one_csv_table(cachesim(kConfigurations + " --per-level - --format csv"), level_columns()), "");
  EXPECT_EQ(one_csv_table(cachesim(kConfigurations + " --per-frame - --format csv"), frame_columns()), "");
  EXPECT_EQ(one_csv_table(cachesim("--scheme single,split --sample-windows 1/2 --window-records 64 --format csv"),
                          sampled_columns()),
            "");
  EXPECT_EQ(one_csv_table(cachesim("--curve --assoc 1,full --format csv"), kCurveColumns), "");
}

// Issue 22 item 2: per-level rows of configurations that share scheme and
// size are told apart by the other configuration columns.
TEST_F(OutputTables, PerLevelRowsAreTidy) {
  const auto rows = csv_rows(cachesim(kConfigurations + " --per-level - --format csv"));
  ASSERT_GT(rows.size(), 1u);
  std::set<std::vector<std::string>> keys;  // configuration and level: one row each
  for (std::size_t r = 1; r < rows.size(); ++r) {
    std::vector<std::string> key(rows[r].begin(), rows[r].begin() + 11);
    EXPECT_TRUE(keys.insert(key).second) << "two rows for one configuration and level, row " << r + 1;
  }
}

TEST_F(OutputTables, CachesimRunJsonHasOneShapeWhateverTheOptions) {
  expect_json_table(cachesim(kConfigurations + " --format json"), main_columns(), "run");
  expect_json_table(cachesim(kConfigurations + " --per-level " + shell_quoted(path("l.json")) + " --per-frame " +
                             shell_quoted(path("f.json")) + " --format json"),
                    main_columns(), "run with side tables");
  expect_json_table(read_file(path("l.json")), level_columns(), "per-level");
  expect_json_table(read_file(path("f.json")), frame_columns(), "per-frame");
  expect_json_table(cachesim("--scheme single,split --sample-windows 1/2 --window-records 64 --format json"),
                    sampled_columns(), "sampled");
  expect_json_table(cachesim("--curve --assoc 1,full --format json"), kCurveColumns, "curve");
}

TEST_F(OutputTables, DineroWrapRunIsOneTable) {
  const std::string command = shell_quoted(program("dinero-wrap")) + " run " + shell_quoted(trace_) +
                              " --size 1k --scheme single,split --high-policy cache --dinero \"" +
                              program("cachesim").string() + " dinero\" --format ";
  const auto csv = run_command(command + "csv");
  ASSERT_EQ(csv.exit_code, 0) << csv.err;
  EXPECT_EQ(one_csv_table(csv.out, main_columns()), "");
  const auto json = run_command(command + "json");
  ASSERT_EQ(json.exit_code, 0) << json.err;
  expect_json_table(json.out, main_columns(), "dinero-wrap");
}

TEST_F(OutputTables, TracetoolInfoIsOneTableOrOneObject) {
  const std::string command = shell_quoted(program("tracetool")) + " info " + shell_quoted(trace_) + " --format ";
  const auto csv = run_command(command + "csv");
  ASSERT_EQ(csv.exit_code, 0) << csv.err;
  EXPECT_EQ(one_csv_table(csv.out, {"field", "value"}), "");
  EXPECT_NE(csv.out.find("\nheader.layout.node_size,8\n"), std::string::npos) << csv.out;
  const auto json = run_command(command + "json");
  ASSERT_EQ(json.exit_code, 0) << json.err;
  EXPECT_TRUE(nlohmann::json::parse(json.out).is_object());
}

}  // namespace
}  // namespace nodetrace::testing
