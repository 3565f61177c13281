// scripts/experiments.mk without a target, and with a RUN launcher that is
// not installed (issue 52 item 12): help rather than every study, and a
// check that names the missing program before anything runs.
#include <gtest/gtest.h>

#include <filesystem>
#include <sstream>
#include <string>

#include "test_support.hpp"

namespace nodetrace::testing {
namespace {

// `make -f scripts/experiments.mk ARGUMENTS` into `out`, standard error after standard output.
CommandResult make(const std::string& arguments, const std::filesystem::path& out) {
  const auto build = std::filesystem::path(NODETRACE_BIN_DIR).parent_path();
  return run_command("env -u MAKEFLAGS -u MFLAGS -u MAKELEVEL make --no-print-directory -C " +
                     shell_quoted(NODETRACE_SOURCE_DIR) + " -f scripts/experiments.mk BUILD=" + shell_quoted(build) +
                     " OUT=" + shell_quoted(out) + " " + arguments + " 2>&1");
}

TEST(ExperimentsHelp, NoTargetPrintsEveryStudyWithItsLineAndRunsNothing) {
  TempDir dir;
  // RUN=false: were a study to start, its first render would fail at once.
  const auto bare = make("RUN=false", dir / "out");
  ASSERT_EQ(bare.exit_code, 0) << bare.out;
  EXPECT_EQ(make("RUN=false help", dir / "out").out, bare.out);
  EXPECT_FALSE(std::filesystem::exists(dir / "out")) << bare.out;
  std::istringstream lines(bare.out.substr(bare.out.find("\nTargets:\n") + 10));
  std::string line;
  int studies = 0;
  bool all = false;
  while (std::getline(lines, line) && line.rfind("  ", 0) == 0) {
    std::istringstream words(line);
    std::string target, first_word;
    words >> target >> first_word;
    EXPECT_FALSE(first_word.empty()) << "no description for " << target;
    all = all || target == "all";
    if (!all) ++studies;
  }
  EXPECT_GE(studies, 14) << bare.out;
  for (const char* target : {"  table1 ", "  policies ", "  convergence ", "  all ", "  clean "}) {
    EXPECT_NE(bare.out.find(target), std::string::npos) << target << " in\n" << bare.out;
  }
  // scripts/table1.mk keeps table1 as its default.
  EXPECT_EQ(make("-f scripts/table1.mk -n SCENES=forest WIDTH=8 HEIGHT=6", dir / "out").out.find("Targets:"),
            std::string::npos);
}

TEST(ExperimentsHelp, ALauncherThatIsNotInstalledIsNamedBeforeAnythingRuns) {
  TempDir dir;
  const auto missing = make("RUN='no-such-launcher --ntasks=1' table1 SCENES=forest WIDTH=8 HEIGHT=6", dir / "out");
  EXPECT_EQ(missing.exit_code, 2) << missing.out;
  EXPECT_NE(missing.out.find("RUN=\"no-such-launcher --ntasks=1\": no program 'no-such-launcher' on PATH"),
            std::string::npos)
      << missing.out;
  EXPECT_EQ(missing.out.find("not found"), std::string::npos) << missing.out;
  EXPECT_FALSE(std::filesystem::exists(dir / "out" / "table1")) << missing.out;
  // help needs no launcher; one that exists passes the check.
  EXPECT_EQ(make("RUN=no-such-launcher help", dir / "out").exit_code, 0);
  EXPECT_EQ(make("RUN=env -n table1 SCENES=forest WIDTH=8 HEIGHT=6", dir / "out").exit_code, 0);
}

}  // namespace
}  // namespace nodetrace::testing
