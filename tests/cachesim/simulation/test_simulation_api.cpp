// cachesim's simulation API driven as a library (what the Python module
// does): options filled in, checked by SimulationPlan, a trace's batches fed
// one by one, and the report cachesim run prints for the same trace; a wrong
// value raises the UsageError cachesim run reports.
#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

#include "nodetrace/base/error.hpp"
#include "nodetrace/cachesim/simulation/run_arguments.hpp"
#include "nodetrace/cachesim/simulation/simulation.hpp"
#include "nodetrace/formats/read/trace_reader.hpp"
#include "test_support.hpp"

namespace nodetrace::cachesim {
namespace {

using testing::program;
using testing::run_command;
using testing::shell_quoted;

class SimulationApi : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new testing::TempDir;
    const auto rendered = run_command(shell_quoted(program("tracer")) +
                                      " render mountain --width 64 --height 48 -q --high-size 4k -o " +
                                      shell_quoted(trace()));
    ASSERT_EQ(rendered.exit_code, 0) << rendered.err;
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }
  static std::string trace() { return (*dir_ / "t.din.zst").string(); }
  static testing::CommandResult cachesim_run(const std::string& arguments) {
    return run_command(shell_quoted(program("cachesim")) + " run " + shell_quoted(trace()) + " " + arguments);
  }

  // The options of `cachesim run TRACE --size 4k,8k --scheme single,split --assoc 1,full --format csv`.
  static SimulationOptions two_schemes() {
    SimulationOptions options;
    options.traces = {trace()};
    options.sizes = {"4k", "8k"};
    options.sizes_given = true;
    options.schemes = {"single", "split"};
    options.assocs = {"1", "full"};
    options.format = "csv";
    return options;
  }
  static constexpr const char* kTwoSchemes = "--size 4k,8k --scheme single,split --assoc 1,full --format csv";

 private:
  static testing::TempDir* dir_;
};

testing::TempDir* SimulationApi::dir_ = nullptr;

TEST_F(SimulationApi, FedBatchesGiveTheRowsOfCachesimRunCsv) {
  const SimulationPlan plan(two_schemes());
  auto reader = formats::TraceReader::open(trace(), plan.reader_options());
  const SimulationMode mode = plan.mode_for({reader.get()});
  ASSERT_EQ(mode, SimulationMode::Sweep);
  std::unique_ptr<Simulation> simulation = plan.start(mode, *reader, trace());
  ASSERT_NE(simulation, nullptr);
  formats::RecordBatch batch;
  std::size_t batches = 0;
  while (reader->next(batch)) {
    simulation->feed(batch);
    ++batches;
  }
  EXPECT_GT(batches, 1u) << "the trace should come in several batches";
  const SimulationReport report = plan.report(mode, {simulation->finish()});

  const testing::CommandResult expected = cachesim_run(kTwoSchemes);
  ASSERT_EQ(expected.exit_code, 0) << expected.err;
  EXPECT_EQ(report.out, expected.out);
  EXPECT_EQ(report.err, expected.err);
  EXPECT_EQ(testing::csv_table(report.out).size(), 8u);  // 2 sizes x 2 schemes x 2 assocs
}

TEST_F(SimulationApi, ParsedArgumentsAreTheOptionsFilledIn) {
  SimulationOptions parsed;
  const std::vector<std::string> words = {trace(), "--size", "4k,8k", "--scheme", "single,split",
                                          "--assoc", "1,full", "--format", "csv"};
  ASSERT_EQ(parse_run_arguments(words, RunArgumentsSyntax{"cachesim run", "test"}, parsed), std::nullopt);
  const SimulationOptions filled = two_schemes();
  EXPECT_EQ(parsed.traces, filled.traces);
  EXPECT_EQ(parsed.sizes, filled.sizes);
  EXPECT_TRUE(parsed.sizes_given);
  EXPECT_EQ(parsed.schemes, filled.schemes);
  EXPECT_EQ(parsed.assocs, filled.assocs);
  EXPECT_EQ(parsed.format, "csv");
  EXPECT_FALSE(parsed.units.has_value()) << "--units not given";
  // And read whole (simulate) they give the same report as fed.
  const SimulationPlan plan(parsed);
  auto reader = formats::TraceReader::open(trace(), plan.reader_options());
  const SimulationMode mode = plan.mode_for({reader.get()});
  EXPECT_EQ(plan.report(mode, {plan.simulate(mode, *reader, trace())}).out, cachesim_run(kTwoSchemes).out);
}

// The message of SimulationPlan's UsageError for `options`, or "" when none.
std::string usage_error(const SimulationOptions& options) {
  try {
    const SimulationPlan plan(options);
  } catch (const base::UsageError& error) {
    return error.what();
  }
  return "";
}

TEST_F(SimulationApi, WrongValuesRaiseCachesimRunsUsageError) {
  struct Case {
    const char* arguments;  // for cachesim run
    void (*set)(SimulationOptions&);
    const char* option;  // named in the message
  };
  const Case cases[] = {
      {"--size 3k", [](SimulationOptions& o) { o.sizes = {"3k"}; }, "--size"},
      {"--assoc 0", [](SimulationOptions& o) { o.assocs = {"0"}; }, "--assoc"},
      {"--policy lfu", [](SimulationOptions& o) { o.policies = {"lfu"}; }, "--policy"},
      {"--split-level x", [](SimulationOptions& o) { o.split_levels = {"x"}; }, "--split-level"},
      {"--window-records 0", [](SimulationOptions& o) { o.window_records = 0; }, "--window-records"},
      {"--l2-block 32", [](SimulationOptions& o) { o.l2_block = 32; }, "--l2-block"},
  };
  for (const Case& c : cases) {
    SimulationOptions options;
    options.traces = {trace()};
    c.set(options);
    const std::string message = usage_error(options);
    EXPECT_NE(message.find(c.option), std::string::npos) << c.arguments << ": " << message;
    const testing::CommandResult run = cachesim_run(c.arguments);
    EXPECT_EQ(run.exit_code, 2) << c.arguments;
    EXPECT_EQ(run.err, "cachesim run: " + message + "\n") << c.arguments;
  }
}

TEST_F(SimulationApi, ValuesTheCommandLineRefusesAreRefusedFilledIn) {
  // cachesim run's parser refuses these names; a caller filling the struct gets a UsageError naming the option.
  SimulationOptions fetch;
  fetch.fetch = "never";
  EXPECT_EQ(usage_error(fetch),
            "--fetch: 'never' is not one of demand, always, miss, tagged, load-forward, subblock");
  SimulationOptions format;
  format.format = "xml";
  EXPECT_EQ(usage_error(format), "--format: 'xml' is not one of table, csv, json");
  SimulationOptions units;
  units.units = "some";
  EXPECT_EQ(usage_error(units), "--units: 'some' is not one of shared, private");
  SimulationOptions informat;
  informat.informat = "text";
  try {
    SimulationPlan plan(informat);
    plan.reader_options();
    ADD_FAILURE() << "--informat text accepted";
  } catch (const base::UsageError& error) {
    EXPECT_STREQ(error.what(), "--informat: 'text' is not one of din, xdin, binary");
  }
}

}  // namespace
}  // namespace nodetrace::cachesim
