// Outputs are told apart by the file each name reaches, not by spelling:
// device and inode where the file exists, the resolved path where it does
// not; a character device takes any number of outputs.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <string>

#include "nodetrace/base/error.hpp"
#include "nodetrace/cli/distinct_outputs.hpp"
#include "test_support.hpp"

namespace nodetrace::cli {
namespace {

namespace fs = std::filesystem;
using nodetrace::testing::TempDir;
using nodetrace::testing::write_file;

std::string usage_error_of(const std::vector<NamedOutput>& outputs) {
  try {
    check_distinct_outputs(outputs);
  } catch (const base::UsageError& error) {
    return error.what();
  }
  return {};
}

TEST(SameOutputFile, NewNamesSpelledDifferentlyAreOneFile) {
  TempDir dir;
  fs::create_directory(dir / "sub");
  const std::string plain = (dir / "s.din").string();
  EXPECT_TRUE(same_output_file(plain, (dir / "." / "s.din").string()));
  EXPECT_TRUE(same_output_file(plain, (dir / "sub" / ".." / "s.din").string()));
  EXPECT_FALSE(same_output_file(plain, (dir / "t.din").string()));
  EXPECT_FALSE(fs::exists(plain));  // only looked at
}

TEST(SameOutputFile, ARelativeNameAndItsAbsoluteFormAreOneFile) {
  TempDir dir;
  const fs::path before = fs::current_path();
  fs::current_path(dir.path());
  const bool same = same_output_file("s.din", "./s.din") && same_output_file("s.din", (dir / "s.din").string());
  fs::current_path(before);
  EXPECT_TRUE(same);
}

TEST(SameOutputFile, ExistingFileByLinksIsOneFile) {
  TempDir dir;
  write_file(dir / "s.din", "x");
  fs::create_symlink("s.din", dir / "soft.din");
  fs::create_hard_link(dir / "s.din", dir / "hard.din");
  const std::string file = (dir / "s.din").string();
  EXPECT_TRUE(same_output_file(file, (dir / "soft.din").string()));
  EXPECT_TRUE(same_output_file(file, (dir / "hard.din").string()));
  write_file(dir / "other.din", "x");
  EXPECT_FALSE(same_output_file(file, (dir / "other.din").string()));
}

TEST(SameOutputFile, ADanglingLinkIsTheFileItWouldCreate) {
  TempDir dir;
  fs::create_symlink("new.din", dir / "link.din");
  EXPECT_TRUE(same_output_file((dir / "link.din").string(), (dir / "new.din").string()));
}

TEST(SameOutputFile, ACharacterDeviceTakesEveryOutputAndStandardOutputIsOneStream) {
  EXPECT_FALSE(same_output_file("/dev/null", "/dev/null"));
  EXPECT_TRUE(same_output_file("-", "-"));
}

TEST(CheckDistinctOutputs, NamesBothOptionsAndBothSpellings) {
  TempDir dir;
  const std::string a = (dir / "s.din").string();
  const std::string b = (dir / "." / "s.din").string();
  EXPECT_EQ(usage_error_of({{"-o", a}, {"--image", (dir / "x.png").string()}, {"--report", b}}),
            "-o '" + a + "' and --report '" + b + "' name one file: one output each; write one of them to another file");
  EXPECT_EQ(usage_error_of({{"--per-level", "p.csv"}, {"--per-frame", "p.csv"}}),
            "--per-level and --per-frame both name 'p.csv': one output each; write one of them to another file");
  EXPECT_EQ(usage_error_of({{"-o", a}, {"-o", b}}),
            "-o names the same file twice ('" + a + "' and '" + b + "'), for two outputs: one output each; write "
            "one of them to another file");
  EXPECT_EQ(usage_error_of({{"--per-level", ""}, {"--per-frame", ""}, {"--per-unit", a}}), "");  // "" is none
}

}  // namespace
}  // namespace nodetrace::cli
