// tracer render --simulate "OPTIONS" --report FILE: the report, and every
// table it writes, equal byte for byte what cachesim run OPTIONS prints over
// the container traces the same render writes; its options are cachesim
// run's, with cachesim's messages and exit status, checked before rendering.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "test_support.hpp"

namespace nodetrace {
namespace {

using testing::program;
using testing::read_file;
using testing::run_command;
using testing::TempDir;

std::string tracer() { return program("tracer").string(); }
std::string cachesim() { return program("cachesim").string(); }

// Renders `render` once writing the traces `traces` (-o's pattern) and
// simulating `simulate` with side tables `tables` (names in `simulate`
// written as ".../in-NAME"), then runs cachesim over the written traces
// `written` with the same options (tables ".../out-NAME"), and compares.
void expect_report_as_cachesim_run(const std::string& render, const std::string& traces,
                                   const std::vector<std::string>& written, const std::string& simulate,
                                   const std::vector<std::string>& tables = {}) {
  TempDir dir;
  std::string in_options = simulate, out_options = simulate;
  for (const auto& table : tables) {
    const auto at = simulate.find(table);
    ASSERT_NE(at, std::string::npos) << table;
    in_options.replace(in_options.find(table), table.size(), (dir / ("in-" + table)).string());
    out_options.replace(out_options.find(table), table.size(), (dir / ("out-" + table)).string());
  }
  const auto rendered = run_command("cd " + testing::shell_quoted(dir.path()) + " && " + render + " -q -o '" +
                                    traces + "' --simulate '" + in_options + "' --report in-report");
  ASSERT_EQ(rendered.exit_code, 0) << rendered.err;
  std::string names;
  for (const auto& trace : written) names += " " + trace;
  const auto simulated = run_command("cd " + testing::shell_quoted(dir.path()) + " && " + cachesim() + " run" +
                                     names + " " + out_options);
  ASSERT_EQ(simulated.exit_code, 0) << simulated.err;
  ASSERT_GT(simulated.out.size() + tables.size(), 0u);
  EXPECT_EQ(read_file(dir / "in-report"), simulated.out);
  EXPECT_EQ(rendered.err, simulated.err);  // notes of CSV and JSON reports
  for (const auto& table : tables) {
    const std::string expected = read_file(dir / ("out-" + table));
    EXPECT_GT(expected.size(), 50u) << table;
    EXPECT_EQ(read_file(dir / ("in-" + table)), expected) << table;
  }
}

const std::string kRender = " render mountain:6 --width 40 --height 30 --threads 2";

TEST(InRenderSimulation, EveryLayoutOfAListSizesAndSchemes) {
  expect_report_as_cachesim_run(tracer() + kRender + " --layout hybrid,dfl,bfl --high-size 1k,4k",
                                "{layout}.din.zst", {"hybrid-1k.din.zst", "hybrid-4k.din.zst", "dfl.din.zst",
                                                     "bfl.din.zst"},
                                "--size 2k,8k --assoc 1,2 --scheme single,split --split-level auto,3");
}

TEST(InRenderSimulation, PerLevelAndPerFrameTablesOfAnAnimation) {
  TempDir scene_dir;
  const std::string scene = testing::write_two_frame_scene(scene_dir.path(), 10).string();
  expect_report_as_cachesim_run(tracer() + " render " + scene +
                                    " --frames 0-1 --width 32 --height 24 --high-size 128",
                                "t.din.zst", {"t.din.zst"},
                                "--size 256 --scheme single,split --format csv --per-level levels.csv "
                                "--per-frame frames.csv",
                                {"levels.csv", "frames.csv"});
}

TEST(InRenderSimulation, PrivateCachesOfTraversalUnitsAndASecondLevel) {
  expect_report_as_cachesim_run(tracer() + kRender + " --rays-in-flight 4 --units 3 --high-size 1k", "u.din.zst",
                                {"u.din.zst"},
                                "--size 2k --scheme single,split --units private --per-unit units.csv "
                                "--l2-size 16k --format json",
                                {"units.csv"});
}

TEST(InRenderSimulation, MissRatioCurve) {
  expect_report_as_cachesim_run(tracer() + kRender + " --high-size 2k", "c.din.zst", {"c.din.zst"},
                                "--curve --scheme single,split --high-size 2k --format csv");
}

TEST(InRenderSimulation, RowSampledRenderAndSampledSimulations) {
  expect_report_as_cachesim_run(tracer() + kRender + " --high-size 1k --sample-rows 1/3 --band-height 2",
                                "s.din.zst", {"s.din.zst"}, "--size 2k --scheme single,split");
  expect_report_as_cachesim_run(tracer() + kRender + " --high-size 1k", "w.din.zst", {"w.din.zst"},
                                "--size 2k --scheme single,split --sample-windows 1/4 --window-records 5000 "
                                "--sample-seed 3 --format csv");
  expect_report_as_cachesim_run(tracer() + kRender, "z.din.zst", {"z.din.zst"},
                                "--size 4k --sample-sets 1/4 --format json");
}

TEST(InRenderSimulation, BvhRecordsAsExtendedDinAndOtherStreams) {
  expect_report_as_cachesim_run(tracer() + kRender + " --accel bvh4 --streams nodes,lists", "b.xdin.zst",
                                {"b.xdin.zst"}, "--size 4k --block 32,64 --assoc 2");
}

TEST(InRenderSimulation, PathTracedRenderWithRaysInFlight) {
  expect_report_as_cachesim_run(tracer() + kRender + " --integrator path --spp 2 --rays-in-flight 8 --layout "
                                                     "hybrid,dfl --high-size 1k",
                                "p-{layout}.din.zst", {"p-hybrid-1k.din.zst", "p-dfl.din.zst"},
                                "--size 2k,4k --assoc 1,4 --scheme single,split --per-level levels.csv",
                                {"levels.csv"});
}

TEST(InRenderSimulation, HardwarePoliciesAndTheOptimum) {
  expect_report_as_cachesim_run(tracer() + kRender + " --high-size 1k", "o.din.zst", {"o.din.zst"},
                                "--size 2k,4k --assoc 4 --policy lru,plru,srrip,brrip,drrip,opt --scheme "
                                "single,split --format csv");
  expect_report_as_cachesim_run(tracer() + kRender + " --high-size 1k", "q.din.zst", {"q.din.zst"},
                                "--curve --policy lru,opt --assoc 1,full --format csv");
}

// The test above compares two runs of one engine: both printed OPT with 0
// misses when it was listed after other policies. Here each opt row of the
// in-render report equals cachesim run of opt alone on the written trace.
TEST(InRenderSimulation, TheOptimumListedAfterOtherPoliciesEqualsItsRunAlone) {
  TempDir dir;
  const std::string in = "cd " + testing::shell_quoted(dir.path()) + " && ";
  const auto rendered = run_command(in + tracer() + kRender + " -q --high-size 1k -o t.din.zst --simulate "
                                    "'--size 2k,4k --assoc 4 --policy lru,fifo,plru,srrip,drrip,opt --format csv' "
                                    "--report r.csv");
  ASSERT_EQ(rendered.exit_code, 0) << rendered.err;
  const auto alone = run_command(in + cachesim() + " run t.din.zst --size 2k,4k --assoc 4 --policy opt --format csv");
  ASSERT_EQ(alone.exit_code, 0) << alone.err;
  const auto report = testing::csv_rows(read_file(dir / "r.csv"));
  const auto expected = testing::csv_rows(alone.out);
  ASSERT_EQ(expected.size(), 3u);
  std::size_t compared = 0;
  for (const auto& row : report) {
    if (row.at(5) != "opt") continue;
    const auto& opt_alone = expected.at(1 + compared++);
    EXPECT_EQ(row, opt_alone);
    EXPECT_GT(std::stoull(row.at(12)), 0u);
  }
  EXPECT_EQ(compared, 2u);
}

TEST(InRenderSimulation, WithoutATraceTheReportNamesEachLayout) {
  TempDir dir;
  const auto rendered = run_command(tracer() + kRender + " -q --layout dfl,hybrid --high-size 1k "
                                    "--simulate '--size 2k --format csv' --report " +
                                    (dir / "r.csv").string());
  ASSERT_EQ(rendered.exit_code, 0) << rendered.err;
  const auto written = run_command(tracer() + kRender + " -q --layout dfl,hybrid --high-size 1k -o " +
                                   (dir / "{layout}.din.zst").string());
  ASSERT_EQ(written.exit_code, 0) << written.err;
  const auto simulated =
      run_command("cd " + testing::shell_quoted(dir.path()) + " && " + cachesim() +
                  " run dfl.din.zst hybrid-1k.din.zst --size 2k --format csv | sed 's/\\.din\\.zst//'");
  EXPECT_EQ(read_file(dir / "r.csv"), simulated.out);
  EXPECT_TRUE(std::filesystem::is_regular_file(dir / "dfl.din.zst"));
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir.path()), {}), 3);  // r.csv and the two traces
}

// Several simulations of one render, each over one layout (LAYOUT=OPTIONS)
// or all: each report is cachesim run's over those layouts' traces.
TEST(InRenderSimulation, EachSimulationOverItsLayoutsIntoItsReport) {
  TempDir dir;
  const std::string in = "cd " + testing::shell_quoted(dir.path()) + " && ";
  const auto rendered = run_command(in + tracer() + kRender + " -q --layout hybrid,bfl --high-size 1k,2k -o "
                                    "'{layout}.din.zst' --simulate 'hybrid-2k=--size 4k --scheme single,split' "
                                    "--report a.txt --simulate '--size 1k,2k --format csv' --report b.csv "
                                    "--simulate 'bfl=--size 8k --format json' --report c.json");
  ASSERT_EQ(rendered.exit_code, 0) << rendered.err;
  const std::pair<std::string, std::string> expected[] = {
      {"a.txt", "hybrid-2k.din.zst --size 4k --scheme single,split"},
      {"b.csv", "hybrid-1k.din.zst hybrid-2k.din.zst bfl.din.zst --size 1k,2k --format csv"},
      {"c.json", "bfl.din.zst --size 8k --format json"}};
  for (const auto& [report, run] : expected) {
    const auto simulated = run_command(in + cachesim() + " run " + run);
    ASSERT_EQ(simulated.exit_code, 0) << simulated.err;
    EXPECT_EQ(read_file(dir / report), simulated.out) << report;
  }
  const auto unknown = run_command(in + tracer() + kRender + " -q --high-size 1k --simulate 'dfl=--size 4k' "
                                   "--report d.txt");
  EXPECT_EQ(unknown.exit_code, 2);
  EXPECT_NE(unknown.err.find("no layout of that name (its layouts: hybrid-1k)"), std::string::npos) << unknown.err;
  EXPECT_EQ(run_command(in + tracer() + kRender + " -q --simulate '--size 4k' --report e --report f").exit_code, 2);
  EXPECT_EQ(run_command(in + tracer() + kRender + " -q --simulate '--size 4k' --report e --simulate '--size 8k' "
                        "--report e").exit_code, 2);
}

// --trace-info: the header tracetool info shows of the trace the render
// would write, and the render's totals of its trailer.
TEST(InRenderSimulation, TraceInfoHoldsTheTracesHeaderAndTheRendersTotals) {
  TempDir dir;
  const std::string in = "cd " + testing::shell_quoted(dir.path()) + " && ";
  ASSERT_EQ(run_command(in + tracer() + kRender + " -q --layout dfl,hybrid --high-size 1k -o '{layout}.din.zst' "
                        "--trace-info '{layout}.json'").exit_code, 0);
  for (const std::string layout : {"dfl", "hybrid-1k"}) {
    const auto info = run_command(in + program("tracetool").string() + " info --format json " + layout + ".din.zst");
    ASSERT_EQ(info.exit_code, 0) << info.err;
    const auto expected = nlohmann::json::parse(info.out);
    const auto got = nlohmann::json::parse(read_file(dir / (layout + ".json")));
    EXPECT_EQ(got.at("header"), expected.at("header")) << layout;
    ASSERT_FALSE(got.at("totals").empty());
    for (const auto& [key, value] : got.at("totals").items()) {
      EXPECT_EQ(value, expected.at("totals").at(key)) << layout << " " << key;
    }
  }
}

// Options cachesim refuses: its message, its exit status, and no render.
TEST(InRenderSimulation, OptionsCachesimRefusesAreRefusedBeforeRendering) {
  TempDir dir;
  const auto trace = (dir / "t.din.zst").string();
  ASSERT_EQ(run_command(tracer() + kRender + " -q -o " + trace).exit_code, 0);
  for (const std::string options : {"--size 3x", "--scheme both", "--curve --size 4k", "--units private --per-level x",
                                    "--sample-windows 1/0", "--bogus", "--size 1g"}) {
    const auto expected = run_command(cachesim() + " run " + trace + " " + options);
    ASSERT_EQ(expected.exit_code, 2) << options;
    const auto report = dir / "r.txt";
    const auto got = run_command(tracer() + " render no-such-scene -q --simulate '" + options + "' --report " +
                                 report.string());
    EXPECT_EQ(got.exit_code, 2) << options;
    const std::string prefix = "tracer render --simulate: ";
    ASSERT_EQ(got.err.rfind(prefix, 0), 0u) << got.err;
    ASSERT_EQ(expected.err.rfind("cachesim run: ", 0), 0u) << expected.err;
    EXPECT_EQ(got.err.substr(prefix.size()), expected.err.substr(std::string("cachesim run: ").size())) << options;
    EXPECT_FALSE(std::filesystem::exists(report));
  }
  const auto named_trace = run_command(tracer() + kRender + " -q --simulate '" + trace + "' --report -");
  EXPECT_EQ(named_trace.exit_code, 2);
}

TEST(InRenderSimulation, AnErrorOfTheSimulationIsCachesimsAndLeavesNoReport) {
  TempDir dir;
  const auto trace = (dir / "t.din.zst").string();
  const std::string options = "--size 64 --scheme split --split-level 9 --high-policy retain";
  ASSERT_EQ(run_command(tracer() + kRender + " -q --high-size 1k -o " + trace).exit_code, 0);
  const auto expected = run_command(cachesim() + " run " + trace + " " + options);
  ASSERT_NE(expected.exit_code, 0) << expected.err;
  const auto got = run_command(tracer() + kRender + " -q --high-size 1k --simulate '" + options + "' --report " +
                               (dir / "r.txt").string());
  EXPECT_EQ(got.exit_code, expected.exit_code);
  // Without -o the trace is named by its layout.
  std::string message = expected.err.substr(std::string("cachesim run: ").size());
  message.replace(0, trace.size(), "hybrid-1k");
  EXPECT_EQ(got.err, "tracer render: " + message);
  EXPECT_FALSE(std::filesystem::exists(dir / "r.txt"));
  EXPECT_TRUE(testing::temporaries(dir.path()).empty());
}

TEST(InRenderSimulation, ReportFollowsTheOutputRules) {
  TempDir dir;
  const auto report = dir / "r.txt";
  testing::write_file(report, "old");
  const auto replaced = run_command(tracer() + kRender + " -q --simulate '--size 4k' --report " + report.string());
  ASSERT_EQ(replaced.exit_code, 0) << replaced.err;
  EXPECT_NE(read_file(report).find("miss_ratio"), std::string::npos);
  const auto missing_folder =
      run_command(tracer() + kRender + " -q --simulate '--size 4k' --report " + (dir / "no/r.txt").string());
  EXPECT_EQ(missing_folder.exit_code, 1);
  EXPECT_NE(missing_folder.err.find("checked before rendering"), std::string::npos) << missing_folder.err;
  EXPECT_EQ(run_command(tracer() + kRender + " -q --simulate '--size 4k'").exit_code, 2);
  EXPECT_EQ(run_command(tracer() + kRender + " -q --report " + report.string()).exit_code, 2);
  EXPECT_EQ(run_command(tracer() + kRender + " -q --simulate '--size 4k' --report - -o -").exit_code, 2);
  const auto to_stdout = run_command(tracer() + kRender + " -q --simulate '--size 4k --format csv' --report -");
  EXPECT_EQ(to_stdout.out.rfind("trace,scheme,size", 0), 0u) << to_stdout.out;
}

}  // namespace
}  // namespace nodetrace
