// `tracer render`'s outputs are checked before the render: two outputs on
// one file or on standard output are a usage error, and an output folder
// that cannot be written fails before any work (the finished trace is not
// thrown away because the image cannot be written).
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "test_support.hpp"

namespace nodetrace::tracer {
namespace {

using nodetrace::testing::program;
using nodetrace::testing::run_command;
using nodetrace::testing::shell_quoted;
using nodetrace::testing::TempDir;

std::string render(const std::string& options) {
  return shell_quoted(program("tracer")) + " render mountain --width 64 --height 48 -q " + options;
}

TEST(RenderOutputs, TraceAndImageBothOnStandardOutputIsAUsageError) {
  const auto result = run_command(render("-o - --image - > /dev/null"));
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.err.find("--image and --output both name '-' (standard output)"), std::string::npos)
      << result.err;
}

TEST(RenderOutputs, TraceAndImageIntoOneFileIsAUsageError) {
  TempDir dir;
  const auto result = run_command(render("-o " + shell_quoted(dir / "x") + " --image " + shell_quoted(dir / "x")));
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.err.find("both name"), std::string::npos) << result.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "x"));
}

// Issue 47's three: one file by two spellings lost the trace (or the image)
// to the other output. Each is refused, naming both options, and nothing is
// written; the trace written before the run is kept.
TEST(RenderOutputs, OneFileByTwoSpellingsIsAUsageErrorNamingBothOptions) {
  TempDir dir;
  const std::string in = "cd " + shell_quoted(dir.path()) + " && ";
  struct Case {
    std::string options, first, second;
  };
  for (const Case& c : {Case{"-o s.din --simulate '--size 1k' --report ./s.din", "--report './s.din'",
                             "--output 's.din'"},
                        Case{"--image same.x --pfm ./same.x", "--image 'same.x'", "--pfm './same.x'"},
                        Case{"-o s.din --trace-info ./s.din", "--trace-info './s.din'", "--output 's.din'"},
                        Case{"-o s.din --simulate '--size 1k --per-level ./s.din' --report r.txt",
                             "--output 's.din'", "--simulate's --per-level './s.din'"},
                        Case{"-o s.din --image ../" + dir.path().filename().string() + "/s.din",
                             "--image '../" + dir.path().filename().string() + "/s.din'", "--output 's.din'"}}) {
    for (const bool exists : {false, true}) {
      if (exists) {
        nodetrace::testing::write_file(dir / "s.din", "kept");
        nodetrace::testing::write_file(dir / "same.x", "kept");
      }
      const auto result = run_command(in + render(c.options));
      EXPECT_EQ(result.exit_code, 2) << c.options;
      EXPECT_NE(result.err.find(c.first + " and " + c.second + " name one file"), std::string::npos)
          << c.options << ": " << result.err;
      if (exists) {
        EXPECT_EQ(nodetrace::testing::read_file(dir / "s.din"), "kept") << c.options;
        EXPECT_EQ(nodetrace::testing::read_file(dir / "same.x"), "kept") << c.options;
      }
      std::filesystem::remove(dir / "s.din");
      std::filesystem::remove(dir / "same.x");
      EXPECT_TRUE(std::filesystem::is_empty(dir.path())) << c.options;
    }
  }
}

// A folder this process cannot create files in, even as root: sysfs's top
// refuses new files to everyone. Empty when this system lets us create one.
std::filesystem::path unwritable_folder() {
  const std::filesystem::path folder = "/sys";
  const auto probe = run_command("touch /sys/nodetrace-probe 2>/dev/null");
  if (probe.exit_code == 0) {
    run_command("rm -f /sys/nodetrace-probe");
    return {};
  }
  return folder;
}

TEST(RenderOutputs, ImageInAFolderThatCannotBeWrittenFailsBeforeRendering) {
  const std::filesystem::path folder = unwritable_folder();
  if (folder.empty()) GTEST_SKIP() << "no folder here refuses new files";
  TempDir dir;
  const auto result = run_command(render("-o " + shell_quoted(dir / "t.din.zst") + " --image " +
                                         shell_quoted(folder / "x.png")));
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_NE(result.err.find("/sys/x.png: cannot write:"), std::string::npos) << result.err;
  EXPECT_NE(result.err.find("(checked before rendering)"), std::string::npos) << result.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "t.din.zst"));
  EXPECT_EQ(nodetrace::testing::temporaries(dir.path()), std::vector<std::string>{});
}

}  // namespace
}  // namespace nodetrace::tracer
