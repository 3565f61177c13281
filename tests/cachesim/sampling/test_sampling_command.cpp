// `cachesim run --sample-windows / --sample-sets` end to end: full coverage
// equals the full run, seeded runs repeat whatever the thread count, bad
// rates are usage errors naming the option.
#include <gtest/gtest.h>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <sstream>

#include "nodetrace/formats/read/trace_reader.hpp"
#include "sampling_trace.hpp"
#include "test_support.hpp"

namespace nodetrace::cachesim {
namespace {

using testing::program;
using testing::run_command;
using testing::shell_quoted;

std::string cachesim() { return shell_quoted(program("cachesim")); }

struct Csv {
  std::vector<std::string> columns;
  std::vector<std::vector<std::string>> rows;
};

Csv parse_csv(const std::string& text) {
  Csv csv;
  std::istringstream lines(text);
  std::string line;
  bool header = true;
  while (std::getline(lines, line)) {
    std::vector<std::string> cells;
    std::istringstream fields(line);
    std::string cell;
    while (std::getline(fields, cell, ',')) cells.push_back(cell);
    if (!line.empty() && line.back() == ',') cells.emplace_back();
    if (header) {
      csv.columns = cells;
      header = false;
    } else {
      csv.rows.push_back(cells);
    }
  }
  return csv;
}

const std::string kConfigs = " --size 256,1k --scheme single,split --format csv";

class SamplingCommand : public ::testing::Test {
 protected:
  void SetUp() override { write_walks(trace_); }
  std::string run(const std::string& options) const {
    const auto result = run_command(cachesim() + " run " + shell_quoted(trace_) + options);
    EXPECT_EQ(result.exit_code, 0) << result.err;
    return result.out;
  }
  testing::TempDir dir_;
  std::filesystem::path trace_ = dir_ / "walks.din.zst";
};

// A copy-back or an invalidation that reaches past its block changes no
// count of another block, so set sampling takes it (harness seed 7001923:
// `c fffffffffffffff7 8` was refused) and, at 1/1, gives the full run's rows.
TEST_F(SamplingCommand, CopyBackAndInvalidationThatReachPastTheirBlockAreTakenBySetSampling) {
  const auto trace = dir_ / "cv.xdin";
  testing::write_file(trace, "r 0 8\nc fffffffffffffff7 8\nr 8 8\nv c 8\nr 0 8\nr 10 8\n");
  const std::string options = " --size 64 --block 8 --assoc 2 --format csv";
  const auto full = run_command(cachesim() + " run " + shell_quoted(trace) + options);
  const auto sampled = run_command(cachesim() + " run " + shell_quoted(trace) + options + " --sample-sets 1/1");
  ASSERT_EQ(full.exit_code, 0) << full.err;
  ASSERT_EQ(sampled.exit_code, 0) << sampled.err;
  const Csv whole = parse_csv(full.out), by_sets = parse_csv(sampled.out);
  ASSERT_EQ(whole.rows.size(), 1u);
  ASSERT_GE(by_sets.rows.size(), 1u);
  EXPECT_EQ(std::vector<std::string>(by_sets.rows[0].begin(), by_sets.rows[0].begin() + 19), whole.rows[0]);
}

TEST_F(SamplingCommand, FullCoverageEqualsTheFullRunWithZeroError) {
  const Csv full = parse_csv(run(kConfigs));
  for (const std::string sampling :
       {" --sample-windows 1/1", " --sample-windows 1/1 --window-records 3000",
        " --sample-sets 1/1", " --sample-windows 1/1 --sample-sets 1/1"}) {
    const Csv sampled = parse_csv(run(kConfigs + sampling));
    std::vector<std::string> columns = full.columns;
    for (const char* name : {"sampled_fraction", "miss_ratio_se", "miss_ratio_low95",
                             "miss_ratio_high95"}) {
      columns.push_back(name);
    }
    ASSERT_EQ(sampled.columns, columns) << sampling;
    ASSERT_EQ(sampled.rows.size(), full.rows.size() + 2) << sampling;  // + two gain rows
    for (std::size_t r = 0; r < full.rows.size(); ++r) {
      const auto& row = sampled.rows[r];
      EXPECT_EQ(std::vector<std::string>(row.begin(), row.begin() + 19), full.rows[r]) << sampling;
      EXPECT_EQ(row[19], "1.000000");
      EXPECT_EQ(row[20], "0.000000");
      EXPECT_EQ(row[21], full.rows[r][13]);
      EXPECT_EQ(row[22], full.rows[r][13]);
    }
    // The gain rows: single minus split, exact, with zero error.
    for (std::size_t g = 0; g < 2; ++g) {
      const auto& gain = sampled.rows[full.rows.size() + g];
      const auto& single = full.rows[2 * g];
      const auto& split = full.rows[2 * g + 1];
      EXPECT_EQ(gain[1], "gain");
      EXPECT_EQ(gain[2], split[2]);
      EXPECT_EQ(gain[12], "");
      const double expected = std::stod(single[12]) / std::stod(single[11]) -
                              std::stod(split[12]) / std::stod(split[11]);
      EXPECT_NEAR(std::stod(gain[13]), expected, 5e-7);
      EXPECT_EQ(gain[20], "0.000000");
      EXPECT_EQ(gain[21], gain[13]);
    }
  }
}

TEST_F(SamplingCommand, SeededRunsRepeatWhateverTheThreadCount) {
  for (const std::string sampling :
       {" --sample-windows 1/4 --window-records 1000 --sample-seed 7", " --sample-sets 1/4 --sample-seed 7",
        " --sample-windows 1/2 --window-records 1500 --sample-sets 1/2 --sample-seed 3"}) {
    const std::string one = run(kConfigs + sampling + " --threads 1");
    EXPECT_EQ(run(kConfigs + sampling + " --threads 1"), one) << sampling;
    EXPECT_EQ(run(kConfigs + sampling + " --threads 2"), one) << sampling;
    EXPECT_EQ(run(kConfigs + sampling + " --threads 4"), one) << sampling;
  }
}

TEST_F(SamplingCommand, QuarterOfTheWindowsSimulatesAQuarterWithAnIntervalAroundIt) {
  const Csv full = parse_csv(run(kConfigs));
  const Csv sampled = parse_csv(run(kConfigs + " --sample-windows 1/4 --window-records 1024"));
  // 40960 records: 40 windows, 10 strata of 4, one window of 1024 each.
  ASSERT_EQ(sampled.rows.size(), 6u);
  for (std::size_t r = 0; r < 4; ++r) {
    const auto& row = sampled.rows[r];
    EXPECT_EQ(row[10], "10240");
    EXPECT_EQ(row[19], "0.250000");
    const double se = std::stod(row[20]);
    const double low = std::stod(row[21]);
    const double high = std::stod(row[22]);
    EXPECT_GT(se, 0.0);
    EXPECT_LE(low, std::stod(row[13]));
    EXPECT_GE(high, std::stod(row[13]));
    // t(0.975, 9) = 2.262; each printed value is rounded to 1e-6 (within 5e-7).
    EXPECT_NEAR(high - low, 2 * 2.262 * se, 2 * 2.262 * 5e-7 + 2 * 5e-7);
    EXPECT_NE(row[12], full.rows[r][12]);
  }
}

TEST_F(SamplingCommand, StandardInputWhichCannotSkipGivesTheSameNumbers) {
  const std::string options = kConfigs + " --sample-windows 1/4 --window-records 1500";
  const Csv file = parse_csv(run(options));
  const auto piped = run_command("cat " + shell_quoted(trace_) + " | " + cachesim() + " run -" + options);
  ASSERT_EQ(piped.exit_code, 0) << piped.err;
  const Csv stdin_csv = parse_csv(piped.out);
  ASSERT_EQ(stdin_csv.rows.size(), file.rows.size());
  for (std::size_t r = 0; r < file.rows.size(); ++r) {
    EXPECT_EQ(stdin_csv.rows[r][0], "-");
    EXPECT_EQ(std::vector<std::string>(stdin_csv.rows[r].begin() + 1, stdin_csv.rows[r].end()),
              std::vector<std::string>(file.rows[r].begin() + 1, file.rows[r].end()));
  }
}

TEST_F(SamplingCommand, RowSampledTraceGetsTheSamplingColumnsWithoutOptions) {
  write_row_sampled(dir_ / "rows.din.zst", 4, 16, 1);
  const auto result = run_command(cachesim() + " run " + shell_quoted(dir_ / "rows.din.zst") + kConfigs);
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const Csv csv = parse_csv(result.out);
  ASSERT_EQ(csv.columns.size(), 23u);
  EXPECT_EQ(csv.columns[19], "sampled_fraction");
  ASSERT_EQ(csv.rows.size(), 6u);
  EXPECT_EQ(csv.rows[0][19], "0.250000");
  EXPECT_EQ(csv.rows[4][1], "gain");
  // An unsampled trace beside it gets the columns too: full coverage, no error.
  const auto both = run_command(cachesim() + " run " + shell_quoted(trace_) + " " +
                                shell_quoted(dir_ / "rows.din.zst") + kConfigs);
  ASSERT_EQ(both.exit_code, 0) << both.err;
  const Csv two = parse_csv(both.out);
  EXPECT_EQ(two.rows[0][19], "1.000000");
  EXPECT_EQ(two.rows[0][20], "0.000000");
  const auto per_level = run_command(cachesim() + " run " + shell_quoted(dir_ / "rows.din.zst") +
                                     " --scheme split --per-level -");
  EXPECT_EQ(per_level.exit_code, 2);
  EXPECT_NE(per_level.err.find("is row-sampled"), std::string::npos) << per_level.err;
  const auto windows = run_command(cachesim() + " run " + shell_quoted(dir_ / "rows.din.zst") +
                                   " --sample-windows 1/2");
  EXPECT_EQ(windows.exit_code, 2);
  EXPECT_NE(windows.err.find("--sample-windows"), std::string::npos) << windows.err;
}

TEST_F(SamplingCommand, BadRatesAreUsageErrorsNamingTheOption) {
  for (const std::string option : {"--sample-windows", "--sample-sets"}) {
    for (const std::string rate : {"1/0", "3/2", "abc", "1/", "/4", "1/4x", "0/4"}) {
      const auto result =
          run_command(cachesim() + " run " + shell_quoted(trace_) + " " + option + " " + rate);
      EXPECT_EQ(result.exit_code, 2) << option << " " << rate;
      EXPECT_NE(result.err.find(option + ": '" + rate + "' is not a sampling rate"),
                std::string::npos)
          << result.err;
    }
  }
  const auto zero = run_command(cachesim() + " run " + shell_quoted(trace_) +
                                " --sample-windows 1/2 --window-records 0");
  EXPECT_EQ(zero.exit_code, 2);
  EXPECT_NE(zero.err.find("--window-records"), std::string::npos) << zero.err;
}

TEST_F(SamplingCommand, SetSamplingRefusesCachesWithTooFewSetsAndRatesNotPowersOfTwo) {
  const auto full = run_command(cachesim() + " run " + shell_quoted(trace_) +
                                " --size 1k --assoc full --sample-sets 1/2");
  EXPECT_EQ(full.exit_code, 2);
  EXPECT_NE(full.err.find("has 1 set(s)"), std::string::npos) << full.err;
  const auto small = run_command(cachesim() + " run " + shell_quoted(trace_) +
                                 " --size 256 --sample-sets 1/64");
  EXPECT_EQ(small.exit_code, 2);
  EXPECT_NE(small.err.find("--sample-sets 1/64: the 256-byte cache (block 8) has 32 set(s)"),
            std::string::npos)
      << small.err;
  const auto three = run_command(cachesim() + " run " + shell_quoted(trace_) + " --sample-sets 1/3");
  EXPECT_EQ(three.exit_code, 2);
  EXPECT_NE(three.err.find("--sample-sets 1/3: K must be a power of two"), std::string::npos)
      << three.err;
  const auto blocks = run_command(cachesim() + " run " + shell_quoted(trace_) +
                                  " --block 8,16 --sample-sets 1/2");
  EXPECT_EQ(blocks.exit_code, 2);
  EXPECT_NE(blocks.err.find("one --block"), std::string::npos) << blocks.err;
}

TEST_F(SamplingCommand, SamplingColumnsInTableAndJsonOnlyWhenSampling) {
  const std::string plain = run(" --format json");
  EXPECT_EQ(plain.find("sampled_fraction"), std::string::npos);
  const auto json = nlohmann::json::parse(run(kConfigs.substr(0, kConfigs.find(" --format")) +
                                              " --sample-windows 1/2 --window-records 1024 --format json"))
                        .at("rows");
  ASSERT_EQ(json.size(), 6u);
  EXPECT_EQ(json[4]["scheme"], "gain");
  EXPECT_TRUE(json[4]["misses"].is_null());
  EXPECT_TRUE(json[0]["miss_ratio_se"].is_number());
  EXPECT_TRUE(json[4]["miss_ratio_low95"].is_number());
  const std::string table = run(" --sample-windows 1/2 --window-records 1024");
  EXPECT_NE(table.find("miss_ratio_high95"), std::string::npos);
}

TEST_F(SamplingCommand, SamplingRefusesPerLevelPerFrameAndCurve) {
  for (const std::string option : {"--per-level out.csv", "--per-frame out.csv", "--curve"}) {
    const auto result = run_command(cachesim() + " run " + shell_quoted(trace_) +
                                    " --sample-windows 1/2 " + option);
    EXPECT_EQ(result.exit_code, 2) << option;
    EXPECT_NE(result.err.find("not with --per-level"), std::string::npos) << result.err;
  }
}

// docs/guide/sampling.md's command on a trace of fewer windows than K: a sample that
// draws none of them simulates nothing, and says so with exit 1 rather than
// an empty miss ratio and exit 0.
TEST_F(SamplingCommand, SampleOfNoRecordsIsExit1SayingWhy) {
  const auto result = run_command(cachesim() + " run " + shell_quoted(trace_) +
                                  " --size 4k --scheme single,split --sample-windows 1/16 --sample-seed 1"
                                  " --window-records 100000000");
  EXPECT_EQ(result.exit_code, 1) << result.out;
  EXPECT_EQ(result.out, "");
  EXPECT_NE(result.err.find("the sample simulated none of the trace's"), std::string::npos) << result.err;
  // Issue 52 item 12: the trace is shorter than a window; the window is all its records.
  const auto reader = formats::TraceReader::open(trace_.string());
  const std::string records = reader->trailer()->totals.at("records").dump();
  EXPECT_NE(result.err.find("the sample simulated none of the trace's " + records + " records: --sample-windows 1/16 "
                            "drew none of its 1 window (all " + records + " records; a window is 100000000 records)"),
            std::string::npos)
      << result.err;
  // The same trace with a window drawn: a report, exit 0.
  EXPECT_FALSE(run(" --size 4k --sample-windows 1/1 --window-records 100000000 --format csv").empty());
}

}  // namespace
}  // namespace nodetrace::cachesim
