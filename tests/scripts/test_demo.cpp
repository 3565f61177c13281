// scripts/demo.sh at a tenth of its size (a tracer that renders 80x60 stands
// in for the real one): each report names the trace it describes, a file
// that is there, and is what cachesim run says of that file.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "test_support.hpp"

namespace nodetrace::testing {
namespace {

namespace fs = std::filesystem;

// Issue 47: the reports named out/demo-hybrid-2k.din.zst, which the script
// had renamed to out/demo-4k.din.zst.
TEST(Demo, EachReportNamesTheTraceItDescribes) {
  TempDir dir;
  fs::create_directories(dir / "scripts");
  for (const char* file : {"demo.sh", "paper-table1.csv"}) {
    fs::copy_file(fs::path(NODETRACE_SOURCE_DIR) / "scripts" / file, dir / "scripts" / file);
  }
  fs::create_directories(dir / "build" / "bin");
  write_file(dir / "build" / "bin" / "tracer",
             "#!/bin/sh\n"
             "# The real tracer at 80x60 instead of the demo's 800x600.\n"
             "n=$#\nprev=\n"
             "for a; do\n"
             "  value=$a\n"
             "  case \"$prev\" in --width) value=80 ;; --height) value=60 ;; esac\n"
             "  set -- \"$@\" \"$value\"\n"
             "  prev=$a\n"
             "done\n"
             "shift \"$n\"\n"
             "exec " + shell_quoted(program("tracer")) + " \"$@\"\n");
  fs::permissions(dir / "build" / "bin" / "tracer", fs::perms::owner_all);
  const std::string in = "cd " + shell_quoted(dir.path()) + " && ";
  const auto demo = run_command(in + "bash scripts/demo.sh --skip-setup --build-dir build");
  ASSERT_EQ(demo.exit_code, 0) << demo.err;
  EXPECT_NE(demo.out.find("4 KB "), std::string::npos) << demo.out;
  for (const std::string size : {"4", "8", "16"}) {
    const std::string trace = "out/demo-" + size + "k.din.zst";
    ASSERT_TRUE(fs::exists(dir / trace)) << trace;
    const std::string csv = read_file(dir / ("out/demo-" + size + "k.csv"));
    const auto rows = csv_rows(csv);
    ASSERT_EQ(rows.size(), 3u) << csv;  // header, single, split
    for (std::size_t r = 1; r < rows.size(); ++r) EXPECT_EQ(rows[r].at(0), trace) << csv;
    const auto rerun = run_command(in + shell_quoted(program("cachesim")) + " run " + trace + " --size " + size +
                                   "k --block 8 --assoc 1 --scheme single,split --split-level auto --format csv");
    ASSERT_EQ(rerun.exit_code, 0) << rerun.err;
    EXPECT_EQ(rerun.out, csv) << trace;
  }
  for (const auto& entry : fs::directory_iterator(dir / "out")) {
    EXPECT_EQ(entry.path().filename().string().find("hybrid"), std::string::npos) << entry.path();
  }
}

}  // namespace
}  // namespace nodetrace::testing
