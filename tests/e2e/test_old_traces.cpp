// Old traces stay readable (issue 52): traces written by earlier versions of
// the tracer (tests/data/old-traces/, README.md there says how each was made)
// verify and simulate with today's programs, with the counts the programs
// that wrote them gave, and with real Dinero IV's (expected.json).
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <map>
#include <string>

#include "test_support.hpp"

namespace nodetrace::testing {
namespace {

const std::filesystem::path kOldTraces = std::filesystem::path(NODETRACE_SOURCE_DIR) / "tests" / "data" / "old-traces";

nlohmann::json expected_counts() {
  return nlohmann::json::parse(read_file(kOldTraces / "expected.json"));
}

std::string plural(std::uint64_t count, const std::string& noun) {
  return std::to_string(count) + " " + noun + (count == 1 ? "" : "s");
}

// The total of a "Demand Fetches" or "Demand Misses" row of Dinero's output.
std::uint64_t dinero_total(const std::string& output, const std::string& row) {
  const std::size_t at = output.find("\n " + row);
  EXPECT_NE(at, std::string::npos) << output;
  return at == std::string::npos ? 0 : std::stoull(output.substr(at + row.size() + 2));
}

std::string dinero_options(const nlohmann::json& dinero, const nlohmann::json& row) {
  return "-informat " + dinero.at("informat").get<std::string>() + " -l1-usize " + row.at("size").get<std::string>() +
         " -l1-ubsize 8 -l1-uassoc 1";
}

TEST(OldTraces, EveryOneIsListedWithItsCounts) {
  const nlohmann::json expected = expected_counts();
  std::size_t traces = 0;
  for (const auto& entry : std::filesystem::directory_iterator(kOldTraces)) {
    if (entry.path().extension() != ".zst") continue;
    ++traces;
    EXPECT_TRUE(std::any_of(expected.begin(), expected.end(),
                            [&](const nlohmann::json& e) { return e.at("file") == entry.path().filename().string(); }))
        << entry.path().filename() << " has no expected counts";
  }
  EXPECT_EQ(traces, expected.size());
  EXPECT_GE(traces, 5u);
}

TEST(OldTraces, TracetoolVerifiesEveryOneFromAFileAndAPipe) {
  for (const nlohmann::json& trace : expected_counts()) {
    const std::string file = shell_quoted(kOldTraces / trace.at("file").get<std::string>());
    const std::string ok = "OK: " + plural(trace.at("records"), "record") + ", " +
                           plural(trace.at("animation_frames"), "animation frame") + ", " +
                           plural(trace.at("data_frames"), "data frame") + "\n";
    const auto from_file = run_command(shell_quoted(program("tracetool")) + " verify " + file);
    EXPECT_EQ(from_file.exit_code, 0) << trace.at("file") << ": " << from_file.err;
    EXPECT_EQ(from_file.out, ok) << trace.at("file");
    const auto from_pipe = run_command("cat " + file + " | " + shell_quoted(program("tracetool")) + " verify -");
    EXPECT_EQ(from_pipe.exit_code, 0) << trace.at("file") << ": " << from_pipe.err;
    EXPECT_EQ(from_pipe.out, ok) << trace.at("file");
  }
}

TEST(OldTraces, CachesimRunGivesTheCountsOfTheVersionThatWroteThem) {
  for (const nlohmann::json& trace : expected_counts()) {
    const std::string file = shell_quoted(kOldTraces / trace.at("file").get<std::string>());
    const auto run = run_command(shell_quoted(program("cachesim")) + " run " + file + " " +
                                 trace.at("cachesim_run").at("options").get<std::string>() + " --format csv");
    ASSERT_EQ(run.exit_code, 0) << trace.at("file") << ": " << run.err;
    const auto rows = csv_rows(run.out);
    ASSERT_GT(rows.size(), 1u) << run.out;
    // Today's rows by scheme and size, each column by name (columns may be added).
    std::map<std::string, std::map<std::string, std::string>> today;
    for (std::size_t r = 1; r < rows.size(); ++r) {
      std::map<std::string, std::string> row;
      for (std::size_t c = 0; c < rows[0].size() && c < rows[r].size(); ++c) row[rows[0][c]] = rows[r][c];
      today[row["scheme"] + " " + row["size"]] = row;
    }
    const nlohmann::json& expected_rows = trace.at("cachesim_run").at("rows");
    ASSERT_FALSE(expected_rows.empty());
    EXPECT_EQ(today.size(), expected_rows.size()) << trace.at("file") << ": " << run.out;
    for (const nlohmann::json& expected : expected_rows) {
      const std::string key = expected.at("scheme").get<std::string>() + " " + expected.at("size").get<std::string>();
      ASSERT_TRUE(today.count(key)) << trace.at("file") << ": no row " << key << " in\n" << run.out;
      for (const auto& [column, value] : expected.items()) {
        ASSERT_TRUE(today[key].count(column)) << trace.at("file") << ": no column " << column;
        EXPECT_EQ(today[key][column], value.get<std::string>()) << trace.at("file") << " " << key << " " << column;
      }
    }
  }
}

TEST(OldTraces, CachesimDineroGivesDineroIVsCounts) {
  for (const nlohmann::json& trace : expected_counts()) {
    const std::string file = shell_quoted(kOldTraces / trace.at("file").get<std::string>());
    const nlohmann::json& dinero = trace.at("dinero");
    for (const nlohmann::json& row : dinero.at("rows")) {
      const auto ours = run_command(shell_quoted(program("cachesim")) + " dinero " + dinero_options(dinero, row) + " " + file);
      ASSERT_EQ(ours.exit_code, 0) << trace.at("file") << ": " << ours.err;
      EXPECT_EQ(dinero_total(ours.out, "Demand Fetches"), row.at("demand_fetches")) << trace.at("file") << " " << row;
      EXPECT_EQ(dinero_total(ours.out, "Demand Misses"), row.at("demand_misses")) << trace.at("file") << " " << row;
    }
  }
}

// The stored Dinero IV counts are Dinero IV's (where it is built).
TEST(OldTraces, StoredDineroCountsAreTheRealDineroIVs) {
  NODETRACE_DINERO_OR_SKIP(real);
  for (const nlohmann::json& trace : expected_counts()) {
    const std::string file = shell_quoted(kOldTraces / trace.at("file").get<std::string>());
    const nlohmann::json& dinero = trace.at("dinero");
    for (const nlohmann::json& row : dinero.at("rows")) {
      const auto theirs = run_command("zstd -dc " + file + " | " + shell_quoted(real) + " " + dinero_options(dinero, row));
      ASSERT_EQ(theirs.exit_code, 0) << trace.at("file") << ": " << theirs.err;
      EXPECT_EQ(dinero_total(theirs.out, "Demand Fetches"), row.at("demand_fetches")) << trace.at("file") << " " << row;
      EXPECT_EQ(dinero_total(theirs.out, "Demand Misses"), row.at("demand_misses")) << trace.at("file") << " " << row;
    }
  }
}

}  // namespace
}  // namespace nodetrace::testing
