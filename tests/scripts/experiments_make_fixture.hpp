// The fixture of the experiment Makefile's tests (test_experiments_make.cpp,
// test_experiments_studies.cpp): a tiny AFF scene standing in for `robot`,
// and `make -f scripts/experiments.mk` run through a launcher that logs every
// render and simulation.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <sstream>
#include <string>

#include "test_support.hpp"

namespace nodetrace::testing {

inline std::string quoted(const std::filesystem::path& path) { return shell_quoted(path); }

// A small AFF scene standing in for `robot`, so the tests need no ../shared.
constexpr const char* kTinyScene = R"(v
from 0 1 6
at 0 0 0
up 0 1 0
angle 40
hither 0.1
resolution 32 24
l 2 4 5
f 0.8 0.3 0.2 0.7 0.3 20 0 1
p 4
-2 -1 -2
2 -1 -2
2 -1 2
-2 -1 2
f 0.2 0.6 0.9 0.6 0.4 30 0.5 1
p 3
-1 -1 0
1 -1 0
0 1 0
p 3
-1 -1 -1
0 1 -1
1 -1 -1
p 3
0.5 -1 1
1.5 -1 1
1 0.5 0.5
)";

inline int count_lines_with(const std::string& text, const std::string& word) {
  std::istringstream lines(text);
  int count = 0;
  for (std::string line; std::getline(lines, line);) count += line.find(word) != std::string::npos;
  return count;
}

class ExperimentsMakeTest : public ::testing::Test {
 protected:
  void SetUp() override {
    scene_ = dir_ / "scene" / "tiny.aff";
    std::filesystem::create_directories(scene_.parent_path());
    write_file(scene_, kTinyScene);
    // RUN: the launcher of every render and simulation; this one logs them.
    launcher_ = dir_ / "log-run.sh";
    write_file(launcher_, "#!/bin/sh\necho \"$*\" >> " + quoted(log_) + "\nexec \"$@\"\n");
    std::filesystem::permissions(launcher_, std::filesystem::perms::owner_all);
  }

  // Runs `make -f scripts/experiments.mk TARGET` into `out`; returns what the
  // launcher saw (one line per render or simulation). Table 1's second table
  // (the closest reading) is left out unless `arguments` asks for it.
  std::string make(const std::string& arguments, const std::filesystem::path& out, bool expect_ok = true) {
    std::filesystem::remove(log_);
    const auto build = std::filesystem::path(NODETRACE_BIN_DIR).parent_path();
    const auto result = run_command(
        "env -u MAKEFLAGS -u MFLAGS -u MAKELEVEL make --no-print-directory -C " +
        quoted(NODETRACE_SOURCE_DIR) + " -f scripts/experiments.mk BUILD=" + quoted(build) +
        " OUT=" + quoted(out) + " RUN=" + quoted(launcher_) + " scene_robot=" + quoted(scene_) +
        " SCENES=robot SIZES='1k 4k' CLOSEST_INTERPRETATION= " + arguments + " 2>&1");
    if (expect_ok) {
      EXPECT_EQ(result.exit_code, 0) << result.out;
    }
    output_ = result.out;
    return std::filesystem::exists(log_) ? read_file(log_) : std::string();
  }

  TempDir dir_;
  std::filesystem::path scene_, launcher_, log_ = dir_ / "run.log";
  std::string output_;
};


}  // namespace nodetrace::testing
