// Every row of a report is one cache: a value listed twice, or two names of
// the same cache (`full` and the ways of a one-set cache), give one row and a
// note, in the main report and in --curve.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "nodetrace/cachesim/sweep/config.hpp"
#include "nodetrace/cachesim/sweep/curve.hpp"
#include "test_support.hpp"

namespace nodetrace::cachesim {
namespace {

using testing::program;
using testing::run_command;
using testing::shell_quoted;

class RepeatedRows : public ::testing::Test {
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
  static std::filesystem::path trace() { return *dir_ / "t.din.zst"; }
  static testing::CommandResult cachesim(const std::string& arguments) {
    return run_command(shell_quoted(program("cachesim")) + " run " + shell_quoted(trace()) + " " + arguments);
  }

 private:
  static testing::TempDir* dir_;
};

testing::TempDir* RepeatedRows::dir_ = nullptr;

// The rows after the header that occur more than once.
std::vector<std::string> repeated_lines(const std::string& csv) {
  std::vector<std::vector<std::string>> rows = testing::csv_rows(csv);
  std::vector<std::string> lines;
  for (const auto& row : rows) {
    std::string line;
    for (const auto& cell : row) line += cell + ",";
    lines.push_back(line);
  }
  std::sort(lines.begin(), lines.end());
  std::vector<std::string> repeated;
  for (std::size_t i = 1; i < lines.size(); ++i) {
    if (lines[i] == lines[i - 1]) repeated.push_back(lines[i]);
  }
  return repeated;
}

TEST_F(RepeatedRows, ReadmeCurveCommandPrintsEachCacheOnceWithANote) {
  const auto result = cachesim("--curve --assoc 1,4,full --scheme single,split --high-size 4k --format csv");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_EQ(testing::one_csv_table(result.out), "");
  EXPECT_EQ(repeated_lines(result.out), std::vector<std::string>{}) << result.out;
  // The 4-way curve's one-set point (4 blocks of 8 bytes) is the fully associative 32-byte cache.
  EXPECT_NE(result.out.find("single,8,full,lru,,32,"), std::string::npos) << result.out;
  EXPECT_NE(result.err.find("note: --curve: 2 points repeated an earlier one"), std::string::npos) << result.err;
}

TEST_F(RepeatedRows, ListedTwiceOrNamedTwiceIsOneRowAndANote) {
  for (const std::string options : {"--size 8k,8k", "--size 8k,8192", "--assoc full,full", "--assoc full,1024",
                                    "--scheme split,split"}) {
    const auto result = cachesim(options + " --format csv");
    ASSERT_EQ(result.exit_code, 0) << options << ": " << result.err;
    EXPECT_EQ(testing::csv_rows(result.out).size(), 2u) << options << ":\n" << result.out;
    EXPECT_NE(result.err.find("note: 1 configuration repeated an earlier one"), std::string::npos)
        << options << ": " << result.err;
  }
  const auto distinct = cachesim("--size 4k,8k --format csv");
  EXPECT_EQ(testing::csv_rows(distinct.out).size(), 3u);
  EXPECT_EQ(distinct.err.find("repeated"), std::string::npos) << distinct.err;
}

TEST(MergeRepeatedConfigurations, KeepsTheFirstOfEachInOrder) {
  SweepOptions options;
  options.sizes = {8192, 4096, 8192};
  options.assocs = {0, 1};
  std::vector<Configuration> configs = expand_configurations(options);
  ASSERT_EQ(configs.size(), 6u);
  const auto note = merge_repeated_configurations(configs);
  ASSERT_TRUE(note.has_value());
  EXPECT_NE(note->find("2 configurations"), std::string::npos) << *note;
  ASSERT_EQ(configs.size(), 4u);
  EXPECT_EQ(configs[0].size, 8192u);
  EXPECT_EQ(configs[0].assoc, 1024u);  // full
  EXPECT_EQ(configs[1].assoc, 1u);
  EXPECT_EQ(configs[2].size, 4096u);
  std::vector<Configuration> once = {configs[0], configs[1]};
  EXPECT_FALSE(merge_repeated_configurations(once).has_value());
  EXPECT_EQ(once.size(), 2u);

  options.sizes = {8192};
  options.assocs = {0, 1024};  // the same cache of 1024 blocks
  configs = expand_configurations(options);
  ASSERT_TRUE(merge_repeated_configurations(configs).has_value());
  EXPECT_EQ(configs.size(), 1u);
}

TEST(MergeRepeatedPoints, OneSetCacheOfNWaysIsTheFullyAssociativeOne) {
  CurvePoint four_way{"t", Scheme::Single, 8, 4, ReplacementPolicy::Lru, 0, 32, 10, 5};
  CurvePoint full{"t", Scheme::Single, 8, 0, ReplacementPolicy::Lru, 0, 32, 10, 5};
  CurvePoint larger{"t", Scheme::Single, 8, 4, ReplacementPolicy::Lru, 0, 64, 10, 4};
  std::vector<CurvePoint> points = {four_way, larger, full};
  ASSERT_TRUE(merge_repeated_points(points).has_value());
  ASSERT_EQ(points.size(), 2u);
  EXPECT_EQ(points[0].size, 32u);
  EXPECT_EQ(points[1].size, 64u);
}

}  // namespace
}  // namespace nodetrace::cachesim
