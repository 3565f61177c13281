// `cachesim run`'s usage errors name what was given, and its side tables'
// files are checked before the simulation, not after it.
#include <gtest/gtest.h>

#include <string>

#include "test_support.hpp"

namespace nodetrace::cachesim {
namespace {

using testing::program;
using testing::run_command;
using testing::shell_quoted;

std::string cachesim() { return shell_quoted(program("cachesim")); }

// Two units' records: `0 ADDRESS LEVEL UNIT` under a header that says so.
std::string trace_of_units(const testing::TempDir& dir) {
  const std::string path = (dir / "mu.din.zst").string();
  const auto rendered = run_command(shell_quoted(program("tracer")) +
                                    " render mountain --width 16 --height 12 -q --units 2 -o " + shell_quoted(path));
  EXPECT_EQ(rendered.exit_code, 0) << rendered.err;
  return path;
}

TEST(RunUsageMessages, UnitsPrivateWithPerLevelNamesWhatWasGiven) {
  testing::TempDir dir;
  const std::string trace = trace_of_units(dir);
  const auto per_level = run_command(cachesim() + " run " + shell_quoted(trace) + " --units private --per-level " +
                                     shell_quoted(dir / "x.csv"));
  EXPECT_EQ(per_level.exit_code, 2);
  EXPECT_NE(per_level.err.find("--units private: not with --per-level"), std::string::npos) << per_level.err;
  EXPECT_EQ(per_level.err.find("--l2-size"), std::string::npos) << per_level.err;
  const auto l2 = run_command(cachesim() + " run " + shell_quoted(trace) + " --l2-size 64k --per-frame " +
                              shell_quoted(dir / "y.csv"));
  EXPECT_EQ(l2.exit_code, 2);
  EXPECT_NE(l2.err.find("--l2-size: not with --per-frame"), std::string::npos) << l2.err;
  EXPECT_EQ(l2.err.find("--units private"), std::string::npos) << l2.err;
}

// The trace on standard input is not a trace at all: an error about it means
// the table's file was not checked first.
TEST(RunUsageMessages, TableFileInAMissingFolderFailsBeforeTheTraceIsRead) {
  for (const std::string option : {"--per-level", "--per-frame"}) {
    const auto result = run_command(cachesim() + " run - " + option + " /nonexistent-folder/x.csv", "not a trace\n");
    EXPECT_EQ(result.exit_code, 1) << option;
    EXPECT_NE(result.err.find("/nonexistent-folder/x.csv: cannot write: No such file or directory"), std::string::npos)
        << option << ": " << result.err;
  }
}

// docs/guide/caches.md's `--per-frame frames.csv`: a table file's name chooses CSV or
// JSON, whatever --format gives the main report.
TEST(RunUsageMessages, TableFileNamedCsvOrJsonIsWrittenSo) {
  testing::TempDir dir;
  const std::string trace = trace_of_units(dir);
  const auto result = run_command(cachesim() + " run " + shell_quoted(trace) + " --scheme split --per-frame " +
                                  shell_quoted(dir / "frames.csv") + " --per-level " +
                                  shell_quoted(dir / "levels.json"));
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_EQ(result.out.rfind("trace ", 0), 0u) << result.out;  // the main report: a readable table
  const std::string frames = testing::read_file(dir / "frames.csv");
  EXPECT_EQ(testing::one_csv_table(frames), "") << frames;
  EXPECT_EQ(frames.rfind("trace,frame,scheme,", 0), 0u) << frames;
  const std::string levels = testing::read_file(dir / "levels.json");
  EXPECT_EQ(levels.rfind("{\"columns\": [", 0), 0u) << levels;
}

}  // namespace
}  // namespace nodetrace::cachesim
