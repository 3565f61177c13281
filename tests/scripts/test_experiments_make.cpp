// scripts/experiments.mk at a tiny size: rebuilds are decided by content
// (what changes the records renders again, nothing else does), a table is
// never stale, and outputs are the same bytes from a re-run, whatever -j.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "experiments_make_fixture.hpp"

namespace nodetrace::testing {
namespace {

TEST_F(ExperimentsMakeTest, SecondRunRendersAndSimulatesNothing) {
  const auto out = dir_ / "out";
  const auto first = make("table1 WIDTH=32 HEIGHT=24", out);
  EXPECT_EQ(count_lines_with(first, "render-layouts.sh"), 1) << first;
  // Both simulations inside that render: no trace written, none read.
  EXPECT_EQ(count_lines_with(first, "cachesim run"), 0) << first;
  EXPECT_TRUE(std::filesystem::is_empty(out / "traces") ||
              std::none_of(std::filesystem::directory_iterator(out / "traces"), {},
                           [](const auto& entry) { return entry.path().extension() == ".zst"; }));
  const auto table = read_file(out / "table1" / "table1.csv");
  const auto second = make("table1 WIDTH=32 HEIGHT=24", out);
  EXPECT_EQ(second, "");
  EXPECT_EQ(read_file(out / "table1" / "table1.csv"), table);
  EXPECT_NE(output_.find("| Size |"), std::string::npos) << "the table is printed: " << output_;
}

TEST_F(ExperimentsMakeTest, ChangingWidthChangesTheTableAndChangingBackRendersNothing) {
  const auto out = dir_ / "out";
  make("table1 WIDTH=32 HEIGHT=24", out);
  const auto narrow = read_file(out / "table1" / "table1.csv");
  const auto wider = make("table1 WIDTH=40 HEIGHT=24", out);
  EXPECT_EQ(count_lines_with(wider, "render-layouts.sh"), 1) << wider;
  const auto wide = read_file(out / "table1" / "table1.csv");
  EXPECT_NE(wide, narrow);
  EXPECT_NE(wide.find(",40,24,"), std::string::npos) << wide;
  EXPECT_EQ(narrow.find(",40,24,"), std::string::npos) << narrow;
  // Back to the first width: its traces are still there, the table is its own again.
  const auto back = make("table1 WIDTH=32 HEIGHT=24", out);
  EXPECT_EQ(count_lines_with(back, "render-layouts.sh"), 0) << back;
  EXPECT_EQ(read_file(out / "table1" / "table1.csv"), narrow);
}

TEST_F(ExperimentsMakeTest, TracesAreWrittenAtTraceZstdLevelWhichLeavesTheTableAsItIs) {
  const auto out = dir_ / "out";
  const auto first = make("table1 WIDTH=32 HEIGHT=24 KEEP_TRACES=1", out);
  EXPECT_EQ(count_lines_with(first, "--zstd-level 1"), 1) << first;
  const auto table = read_file(out / "table1" / "table1.csv");
  const auto level3 = make("table1 WIDTH=32 HEIGHT=24 TRACE_ZSTD_LEVEL=3 KEEP_TRACES=1", out);
  EXPECT_EQ(count_lines_with(level3, "render-layouts.sh"), 1) << level3;
  EXPECT_EQ(count_lines_with(level3, "--zstd-level 3"), 1) << level3;
  EXPECT_EQ(read_file(out / "table1" / "table1.csv"), table);
}

TEST_F(ExperimentsMakeTest, SceneContentAndTracerOptionsDecideARenderNotFileTimes) {
  const auto out = dir_ / "out";
  make("table1 WIDTH=32 HEIGHT=24", out);
  // Same bytes, new time: nothing to do.
  write_file(scene_, kTinyScene);
  std::filesystem::last_write_time(scene_, std::filesystem::file_time_type::clock::now());
  EXPECT_EQ(make("table1 WIDTH=32 HEIGHT=24", out), "");
  // A file of the scene's folder changes: every trace of the scene renders again.
  write_file(scene_, std::string(kTinyScene) + "p 3\n-2 0 -2\n-1 0 -2\n-1 1 -2\n");
  EXPECT_EQ(count_lines_with(make("table1 WIDTH=32 HEIGHT=24", out), "render-layouts.sh"), 1);
  // A kd-tree option changes the records too.
  EXPECT_EQ(count_lines_with(make("table1 WIDTH=32 HEIGHT=24 TRAVERSAL_COST=2", out), "render-layouts.sh"), 1);
}

TEST_F(ExperimentsMakeTest, OutputsAreTheSameBytesFromARerunWithAnyJobCount) {
  const auto serial = dir_ / "serial";
  const auto parallel = dir_ / "parallel";
  make("table1 baselines WIDTH=32 HEIGHT=24", serial);
  make("-j2 table1 baselines WIDTH=32 HEIGHT=24", parallel);
  for (const std::string file : {"table1/table1.csv", "table1/table1.md", "table1/table1.png",
                                 "baselines/baselines.csv", "baselines/baselines.md",
                                 "baselines/baselines.png"}) {
    ASSERT_TRUE(std::filesystem::exists(serial / file)) << file;
    EXPECT_TRUE(read_file(serial / file) == read_file(parallel / file)) << file << " differs";
  }
}

// Every render gets --tree-cache $(OUT)/tree-cache, which enters no hash: a
// run with a warm cache makes the same files, under the same names, as the
// cold run before it.
TEST_F(ExperimentsMakeTest, TreeCacheIsUsedAndChangesNoFile) {
  const auto out = dir_ / "out";
  const std::string targets = "table1 sampling WIDTH=32 HEIGHT=24 SAMPLING_SCENES=robot SAMPLING_SIZES=4k "
                              "SAMPLING_METHODS=rows SAMPLING_RATES=2 SAMPLING_SEEDS=1";
  const auto cold = make(targets, out);
  EXPECT_EQ(count_lines_with(cold, "--tree-cache " + (out / "tree-cache").string()), count_lines_with(cold, "render"))
      << cold;
  ASSERT_TRUE(std::filesystem::is_directory(out / "tree-cache"));
  EXPECT_FALSE(std::filesystem::is_empty(out / "tree-cache"));
  // What the cold run made (the sampling study's timings aside), then the same from a warm cache.
  auto made = [&] {
    std::vector<std::pair<std::string, std::string>> files;
    for (const std::string study : {"table1"}) {
      for (const auto& entry : std::filesystem::recursive_directory_iterator(out / study)) {
        if (entry.is_regular_file()) files.emplace_back(entry.path().string(), read_file(entry.path()));
      }
    }
    for (const auto& entry : std::filesystem::directory_iterator(out / "sampling" / "runs")) {
      files.emplace_back(entry.path().filename().string(), "");
    }
    std::sort(files.begin(), files.end());
    return files;
  };
  const auto cold_files = made();
  for (const std::string study : {"table1", "sampling"}) std::filesystem::remove_all(out / study);
  const auto warm = make(targets, out);
  EXPECT_GT(count_lines_with(warm, "--tree-cache"), 0) << warm;
  EXPECT_TRUE(made() == cold_files);
}

// KEEP_TRACES=1: every trace written, cachesim run on each, and the same
// tables, byte for byte, as the simulations inside the renders give.
TEST_F(ExperimentsMakeTest, KeptTracesGiveTheSameTablesAsSimulatingInTheRender) {
  const auto in_render = dir_ / "in-render";
  const auto kept = dir_ / "kept";
  make("table1 baselines WIDTH=32 HEIGHT=24", in_render);
  const auto log = make("table1 baselines WIDTH=32 HEIGHT=24 KEEP_TRACES=1", kept);
  EXPECT_EQ(count_lines_with(log, "render-layouts.sh"), 1) << log;
  EXPECT_EQ(count_lines_with(log, "cachesim run"), 2 + 5) << log;
  for (const std::string file : {"table1/table1.csv", "table1/table1.md", "table1/table1.png",
                                 "baselines/baselines.csv", "baselines/baselines.md", "baselines/baselines.png"}) {
    ASSERT_TRUE(std::filesystem::exists(kept / file)) << file;
    EXPECT_TRUE(read_file(kept / file) == read_file(in_render / file)) << file << " differs";
  }
  // The two ways never share a run: switching renders again rather than mixing them.
  EXPECT_EQ(count_lines_with(make("table1 WIDTH=32 HEIGHT=24", kept), "render-layouts.sh"), 1);
}

// A run simulated in a render that went missing is made again alone (one
// render), the others left as they were.
TEST_F(ExperimentsMakeTest, AMissingRunComesBackFromOneRenderAlone) {
  const auto out = dir_ / "out";
  make("-j2 table1 baselines WIDTH=32 HEIGHT=24", out);
  std::vector<std::filesystem::path> runs;
  for (const auto& entry : std::filesystem::directory_iterator(out / "baselines" / "runs")) {
    if (entry.path().extension() == ".csv") runs.push_back(entry.path());
  }
  ASSERT_EQ(runs.size(), 5u) << "single on dfl, bfl, veb; the hybrid for 1k and 4k";
  std::sort(runs.begin(), runs.end());
  const std::string removed = read_file(runs[2]);
  const auto kept_time = std::filesystem::last_write_time(runs[0]);
  std::filesystem::remove(runs[2]);
  const auto again = make("table1 baselines WIDTH=32 HEIGHT=24", out);
  EXPECT_EQ(count_lines_with(again, "render-layouts.sh"), 1) << again;
  EXPECT_EQ(count_lines_with(again, "--simulate"), 0) << "the launcher sees the script's arguments: " << again;
  EXPECT_EQ(read_file(runs[2]), removed) << "the run made again is the same bytes";
  EXPECT_TRUE(std::filesystem::exists(runs[2].string() + ".trace.json"));
  EXPECT_EQ(std::filesystem::last_write_time(runs[0]), kept_time) << "the runs on disk are not rewritten";
}

// make -n on every target (all is every one; the two-phase studies and
// table1 alone too): it says what it would do, writes nothing, and succeeds.
TEST_F(ExperimentsMakeTest, DryRunOfEveryTargetWritesNothing) {
  const auto out = dir_ / "dry";
  for (const std::string target : {"table1", "calibration", "interpretations", "all"}) {
    const auto log = make("-n " + target + " WIDTH=32 HEIGHT=24 FRAME_STEP=400 ACCEL_SCENES=robot "
                          "SAMPLING_SCENES=robot INFLIGHT_SCENES=robot FRAME_SCENES=robot CAL_SCENES=robot "
                          "INTERP_SCENES=robot INTERP_FINAL_SCENES=robot SENS_SCENES=robot",
                          out);
    EXPECT_EQ(log, "") << target << ": nothing ran";
    EXPECT_FALSE(std::filesystem::exists(out)) << target << ": " << output_;
    EXPECT_NE(output_.find("render-layouts.sh"), std::string::npos) << target << ": " << output_;
    EXPECT_NE(output_.find("write " + out.string()), std::string::npos) << "which manifests: " << output_;
  }
}

// Traces that differ only in their layout come from one render; a trace that
// went missing is rendered again alone, the others left as they were.
TEST_F(ExperimentsMakeTest, LayoutsOfOneRenderAreOneRenderAndAMissingOneComesBack) {
  const auto out = dir_ / "out";
  const auto first = make("-j2 table1 baselines WIDTH=32 HEIGHT=24 KEEP_TRACES=1", out);
  EXPECT_EQ(count_lines_with(first, "render-layouts.sh"), 1) << first;
  std::vector<std::filesystem::path> traces;
  for (const auto& entry : std::filesystem::directory_iterator(out / "traces")) {
    if (entry.path().extension() == ".zst") traces.push_back(entry.path());
  }
  ASSERT_EQ(traces.size(), 5u) << "hybrid for 1k and 4k, dfl, bfl, veb";
  std::sort(traces.begin(), traces.end());
  const std::string removed = read_file(traces[2]);
  const auto kept_time = std::filesystem::last_write_time(traces[0]);
  std::filesystem::remove(traces[2]);
  const auto again = make("table1 baselines WIDTH=32 HEIGHT=24 KEEP_TRACES=1", out);
  EXPECT_EQ(count_lines_with(again, "render-layouts.sh"), 1) << again;
  EXPECT_TRUE(read_file(traces[2]) == removed) << "the trace rendered again is the same bytes";
  EXPECT_EQ(std::filesystem::last_write_time(traces[0]), kept_time) << "the traces on disk are not rewritten";
}

TEST_F(ExperimentsMakeTest, TableShowsThePapersNumbersDirectionsAndParameters) {
  const auto out = dir_ / "out";
  make("table1 WIDTH=32 HEIGHT=24 SIZES='4k 16k'", out);
  const auto markdown = read_file(out / "table1" / "table1.md");
  EXPECT_NE(markdown.find("/ 1.82 ("), std::string::npos) << "Robot 16 KB 'without' beside ours: " << markdown;
  EXPECT_NE(markdown.find("/ hurts ("), std::string::npos) << "Robot 4 KB: the paper's split hurts: " << markdown;
  for (const std::string stated : {"32x24", "traversal cost 1", "intersection cost 1.5", "empty bonus 0.2",
                                   "depth limit", "baseline layout", "K=", "animation frame 0"}) {
    EXPECT_NE(markdown.find(stated), std::string::npos) << stated << " is not stated: " << markdown;
  }
  const auto csv = read_file(out / "table1" / "table1.csv");
  for (const std::string column : {"without_paper", "direction_agrees", "tree_depth_limit", "traversal_cost",
                                   "intersection_cost", "empty_bonus", "layout_without", "split_level", "frame"}) {
    EXPECT_NE(csv.substr(0, csv.find('\n')).find(column), std::string::npos) << column;
  }
}


TEST_F(ExperimentsMakeTest, AnUnknownSceneStopsMakeWithAMessage) {
  make("table1 SCENES=nosuch", dir_ / "out", false);
  EXPECT_NE(output_.find("unknown scene 'nosuch'"), std::string::npos) << output_;
}

// Every target once, on the BART scenes of ../shared (CI), at a tiny size.
TEST_F(ExperimentsMakeTest, EveryTargetRunsAtATinySize) {
  NODETRACE_SHARED_OR_SKIP(shared);
  const auto out = dir_ / "all";
  const auto build = std::filesystem::path(NODETRACE_BIN_DIR).parent_path();
  const auto result = run_command(
      "env -u MAKEFLAGS -u MFLAGS -u MAKELEVEL make --no-print-directory -j2 -C " + quoted(NODETRACE_SOURCE_DIR) +
      " -f scripts/experiments.mk all BUILD=" + quoted(build) + " SHARED=" + quoted(shared) + " OUT=" +
      quoted(out) + " WIDTH=32 HEIGHT=24 SCENES=robot SENS_WIDTH=32 SENS_HEIGHT=24"
      " SENS_K='4 8' SENS_TREE_DEPTHS='16 24' SENS_RESOLUTIONS='16x12 32x24'"
      " CAL_SCENES=robot CAL_WIDTH=16 CAL_HEIGHT=12 CAL_TREE_DEPTHS='16 default' CAL_COSTS=1:1.5"
      " CAL_EMPTY_BONUSES=0.2 CAL_BEST=1 CAL_FINAL_WIDTH=32 CAL_FINAL_HEIGHT=24"
      " FRAME_SCENES='robot kitchen' FRAME_WIDTH=16 FRAME_HEIGHT=12 FRAME_STEP=400"
      " SAMPLING_SCENES=robot SAMPLING_SIZES=4k SAMPLING_RATES='1 4' SAMPLING_SEEDS=1"
      " SAMPLING_WINDOW_RECORDS=512 INTERP_SCENES=robot INTERP_WIDTH=16 INTERP_HEIGHT=12"
      " INTERP_SIZE_MEANINGS='half each highk' INTERP_BASELINES='hybrid bfl' INTERP_HIGH_LOADS=free"
      " INTERP_SPLIT_LEVELS='auto 4' INTERP_TREES='default:1:1.5:0.2:0 default:1:1.5:0.2:2'"
      " INTERP_RAY_SETS='whitted:first primary:all' INTERP_BEST=2 INTERP_FINAL_SCENES='robot forest'"
      " INTERP_FINAL_WIDTH=32 INTERP_FINAL_HEIGHT=24 ACCEL_SCENES=robot ACCEL_KINDS='bvh2 cwbvh8'"
      " ACCEL_LAYOUTS=treelet ACCEL_SIZES=4k"
      " INFLIGHT_SCENES=robot INFLIGHT_WIDTH=16 INFLIGHT_HEIGHT=12 INFLIGHT_RAYS='1 4' INFLIGHT_UNITS='1 2'"
      " POLICY_SCENES=robot POLICY_SIZES=4k POLICY_ASSOCS='1 4' POLICY_WIDTH=16 POLICY_HEIGHT=12"
      " PREFETCH_SCENES=robot PREFETCH_WIDTH=16 PREFETCH_HEIGHT=12 PREFETCH_ACCELS=bvh2 PREFETCH_INTEGRATORS=whitted"
      " PREFETCH_TREELET_BYTES=256"
      " WORKLOADS_SCENES=robot WORKLOADS_WIDTH=16 WORKLOADS_HEIGHT=12 WORKLOADS_SPP=1 WORKLOADS_ACCELS=bvh2"
      " WORKLOADS_RAYS=1 CONV_SCENES=robot CONV_WIDTH=8 CONV_HEIGHT=6 CONV_SPP='1 2' CONV_REFERENCE_SPP=8 2>&1");
  ASSERT_EQ(result.exit_code, 0) << result.out;
  for (const std::string file :
       {"table1/table1.md", "table1/table1.png", "baselines/baselines.md", "baselines/baselines.png",
        "assoc/assoc.md", "assoc/assoc.png", "levels/levels.md", "levels/levels-robot.png",
        "sensitivity/sensitivity.md", "sensitivity/sensitivity.png", "calibration-grid/best.txt",
        "calibration/calibration.md", "calibration/calibration.png", "frames/frames.md", "frames/frames.png",
        "sampling/sampling.md", "sampling/sampling.csv", "sampling/sampling.png",
        "interpretations-grid/best.txt", "interpretations-grid/interpretations-grid.md",
        "interpretations/interpretations.md", "interpretations/interpretations.csv",
        "interpretations/interpretations-cells.csv", "interpretations/interpretations.png", "accel/accel.md",
        "accel/accel.csv", "accel/accel.png", "inflight/inflight.md", "inflight/inflight.csv",
        "inflight/inflight.png", "policies/policies.md", "policies/policies.csv", "policies/policies.png",
        "prefetch/prefetch.md", "prefetch/prefetch.csv", "prefetch/prefetch.png",
        "workloads/workloads.md", "workloads/workloads.csv", "workloads/workloads.png",
        "convergence/convergence.md", "convergence/convergence.csv", "convergence/convergence.png"}) {
    EXPECT_TRUE(std::filesystem::exists(out / file)) << file;
  }
  // Every CSV the targets write (their tables and the runs behind them,
  // per-level tables included) is one table of equal-width rows (issue 22).
  int tables = 0;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(out)) {
    if (entry.path().extension() != ".csv") continue;
    const std::string text = read_file(entry.path());
    const std::string name = entry.path().filename().string();
    const bool level_table = name.ends_with(".levels.csv");
    const std::string wrong = one_csv_table(text);
    EXPECT_EQ(wrong, "") << entry.path();
    if (entry.path().parent_path().filename() == "runs" && !level_table && text.starts_with("trace,")) {
      EXPECT_TRUE(text.starts_with("trace,scheme,size,block,assoc,policy,high_policy,high_size,low_size,split_level,"
                                   "refs,fetches,misses,miss_ratio,"))
          << entry.path();
    }
    if (level_table) {
      EXPECT_TRUE(text.starts_with("trace,scheme,size,block,assoc,policy,high_policy,high_size,low_size,split_level,"
                                   "level,refs,misses\n"))
          << entry.path();
    }
    ++tables;
  }
  EXPECT_GT(tables, 20);
  // Two unit counts x three sizes x two rays in flight, each with an L2 miss ratio.
  const auto inflight = read_file(out / "inflight" / "inflight.csv");
  EXPECT_EQ(count_lines_with(inflight, "robot,"), 12) << inflight;
  EXPECT_EQ(count_lines_with(inflight, "robot,2,4,"), 3) << inflight;
  // Two structures x two blocks x two ways, each 5 single policies and 3 split ones.
  const auto policies = read_file(out / "policies" / "policies.csv");
  EXPECT_EQ(count_lines_with(policies, "robot,kdtree,4096,"), 2 * 2 * 8) << policies;
  EXPECT_EQ(count_lines_with(policies, "robot,bvh2,4096,"), 2 * 2 * 8) << policies;
  EXPECT_EQ(count_lines_with(policies, ",single,opt,"), 2 * 2 * 2) << policies;
  // OPT is a bound with misses of its own: in each cell (scene, structure,
  // size, block, ways) the single cache's OPT misses more than 0 % and no
  // more than any single policy (it once printed 0 % beside the others).
  std::map<std::string, double> opt_of_cell;
  std::vector<std::pair<std::string, double>> single_of_cell;
  for (const auto& row : testing::csv_rows(policies)) {
    if (row.size() < 8 || row.at(5) != "single") continue;
    const std::string cell = row[0] + "," + row[1] + "," + row[2] + "," + row[3] + "," + row[4];
    const double miss_percent = std::stod(row.at(7));
    if (row.at(6) == "opt") opt_of_cell[cell] = miss_percent;
    single_of_cell.emplace_back(cell, miss_percent);
  }
  EXPECT_EQ(opt_of_cell.size(), 2u * 2 * 2) << policies;
  for (const auto& [cell, opt] : opt_of_cell) EXPECT_GT(opt, 0.0) << cell;
  for (const auto& [cell, miss_percent] : single_of_cell) {
    ASSERT_TRUE(opt_of_cell.contains(cell)) << cell;
    EXPECT_LE(opt_of_cell[cell], miss_percent) << cell;
  }
  const auto frames = read_file(out / "frames" / "frames.csv");
  EXPECT_EQ(count_lines_with(frames, "robot,"), 2) << frames;
  EXPECT_EQ(count_lines_with(frames, "kitchen,"), 2) << frames;
  // Three methods x two rates x three quantities; at 1/1 every estimate is the full run's.
  const auto sampling = read_file(out / "sampling" / "sampling.csv");
  EXPECT_EQ(count_lines_with(sampling, "robot,"), 18) << sampling;
  EXPECT_EQ(count_lines_with(sampling, ",1/1,1,single,"), 3) << sampling;
  int exact = 0;
  std::istringstream lines(sampling);
  for (std::string line; std::getline(lines, line);) {
    // abs_error_points 0, and the interval (the point) holds the true value.
    exact += line.find(",1/1,1,") != std::string::npos && line.find(",0.0000,1,") != std::string::npos;
  }
  EXPECT_EQ(exact, 9) << sampling;
  // Sizes x K x baselines x trees x ray sets, a size-by-K reading only with K = 4:
  // (2 + 2 + 1) x 2 x 2 x 2 = 40 readings in the grid, ranked, the best two in best.txt.
  const auto grid = read_file(out / "interpretations-grid" / "interpretations-grid.csv");
  EXPECT_EQ(std::count(grid.begin(), grid.end(), '\n'), 41) << grid;
  EXPECT_EQ(count_lines_with(grid, "highk:"), 8) << grid;
  EXPECT_EQ(count_lines_with(grid, "highk:hybrid:free:auto"), 0) << grid;
  std::istringstream best(read_file(out / "interpretations-grid" / "best.txt"));
  std::vector<std::string> words{std::istream_iterator<std::string>(best), {}};
  EXPECT_EQ(words.size(), 2u);
  // The final phase: the two best and the default, Robot and the forest, with the forest marked a stand-in.
  const auto cells = read_file(out / "interpretations" / "interpretations-cells.csv");
  const auto stand_ins = count_lines_with(cells, "forest,yes,");
  EXPECT_GE(stand_ins, 2 * 2) << cells;
  EXPECT_EQ(count_lines_with(cells, "robot,no,"), stand_ins) << cells;
  EXPECT_NE(read_file(out / "interpretations" / "interpretations.md").find("all 18 mean abs diff (forest stands in)"),
            std::string::npos);
}

TEST_F(ExperimentsMakeTest, Table1UsesTheInterpretationGivenAndShowsTheClosestBesideIt) {
  const auto out = dir_ / "out";
  make("table1 WIDTH=32 HEIGHT=24 INTERPRETATION=size=each,base=bfl,rays=primary", out);
  const auto markdown = read_file(out / "table1" / "table1.md");
  EXPECT_NE(markdown.find("size each, base bfl"), std::string::npos) << markdown;
  EXPECT_NE(markdown.find("rays primary"), std::string::npos) << markdown;
  const auto csv = read_file(out / "table1" / "table1.csv");
  EXPECT_NE(csv.find(",bfl,hybrid,each:bfl:free:auto:"), std::string::npos) << csv;
  EXPECT_EQ(markdown.find("Closest interpretation"), std::string::npos) << markdown;
  // The single cache is the row's size, the split twice it (each cache the row's size).
  EXPECT_NE(csv.find(",1024,1024,"), std::string::npos) << csv;
  // A closest reading adds a second table beside the one used.
  make("table1 WIDTH=32 HEIGHT=24 CLOSEST_INTERPRETATION=each:hybrid:free:auto:default:1:1.5:0.2:0:whitted:first:0",
       out);
  const auto both = read_file(out / "table1" / "table1.md");
  EXPECT_NE(both.find("## Closest interpretation"), std::string::npos) << both;
  EXPECT_NE(both.find("lights first"), std::string::npos) << both;
  // A bad axis stops make with a message naming it.
  make("table1 WIDTH=32 HEIGHT=24 INTERPRETATION=colour=blue", out, false);
  EXPECT_NE(output_.find("unknown axis in 'colour=blue'"), std::string::npos) << output_;
}

}  // namespace
}  // namespace nodetrace::testing
