// Invalidations in `cachesim run`, on every path, as Dinero IV makes them:
// an invalidation removes the block of its address alone, whatever its size
// (d4invalidate), and the first level of --l2-size sees them as the sweep's
// caches do. Both were found by scripts/config-diff.sh.
#include <gtest/gtest.h>

#include <map>
#include <string>
#include <vector>

#include "test_support.hpp"

namespace nodetrace::cachesim {
namespace {

using nodetrace::testing::program;
using nodetrace::testing::run_command;
using nodetrace::testing::shell_quoted;
using nodetrace::testing::TempDir;
using nodetrace::testing::write_file;

class Invalidations : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!std::filesystem::exists(program("cachesim"))) GTEST_SKIP() << "cachesim is not built";
  }
  // The report of `cachesim run` on `records` (xdin, tagged with levels).
  std::vector<std::map<std::string, std::string>> run(const std::string& records, const std::string& options) {
    write_file(dir_ / "t.xdin", records);
    const auto result = run_command(shell_quoted(program("cachesim")) + " run " + shell_quoted(dir_ / "t.xdin") +
                                    " --tags-are-levels --format csv " + options);
    EXPECT_EQ(result.exit_code, 0) << options << ": " << result.err;
    return nodetrace::testing::csv_table(result.out);
  }
  TempDir dir_;
};

// `v 4 8` spans blocks 0 and 1 of 8 bytes; Dinero IV invalidates block 0
// alone, so the second `r 8 8` hits: 4 fetches, 3 misses (Dinero IV's count:
// `cachesim dinero` and dineroIV -l1-usize 64 -l1-ubsize 8 -l1-uassoc 2 agree).
constexpr const char* kSpanningInvalidation = "r 0 8 5\nr 8 8 5\nv 4 8 5\nr 8 8 5\nr 0 8 5\n";

TEST_F(Invalidations, RemoveTheBlockOfTheirAddressAloneUnderEveryPolicy) {
  for (const char* policy : {"lru", "fifo", "random", "plru", "srrip", "brrip", "drrip", "opt"}) {
    for (const char* assoc : {"1", "2", "full"}) {
      const auto rows = run(kSpanningInvalidation, std::string("--size 64 --block 8 --policy ") + policy +
                                                       " --assoc " + assoc);
      ASSERT_EQ(rows.size(), 1u);
      EXPECT_EQ(rows[0].at("fetches"), "4") << policy << " " << assoc;
      EXPECT_EQ(rows[0].at("misses"), "3") << policy << " " << assoc;
    }
  }
}

TEST_F(Invalidations, RemoveTheBlockOfTheirAddressAloneInTheSplitSchemeAndItsTables) {
  // Level 5 goes to the low cache at K 3; under `cache` the same records at level 1 go high.
  const auto split = run(kSpanningInvalidation, "--size 128 --block 8 --assoc 2 --scheme split --split-level 3 "
                                                "--high-policy cache --per-level -");
  ASSERT_EQ(split.size(), 1u);
  EXPECT_EQ(split[0].at("misses"), "3");
  std::string high_records = kSpanningInvalidation;
  for (char& c : high_records) {
    if (c == '5') c = '1';
  }
  const auto high = run(high_records, "--size 128 --block 8 --assoc 2 --scheme split --split-level 3 "
                                      "--high-policy cache");
  ASSERT_EQ(high.size(), 1u);
  EXPECT_EQ(high[0].at("high_misses"), "3");
}

// The first level that feeds --l2-size invalidates as the sweep's caches
// do, so its misses agree with the report's (before, it ignored
// invalidations and the run stopped with exit 1 on a valid trace).
TEST_F(Invalidations, ReachTheFirstLevelOfTheSecondLevelCache) {
  const std::string records = "r 10 8 5\nv 10 8 5\nr 10 8 5\nr 0 8 1\nv 0 8 1\nr 0 8 1\n";
  for (const char* options : {"--scheme single", "--scheme split --split-level 3 --high-policy cache",
                              "--scheme split --split-level 3 --high-policy retain"}) {
    const auto rows = run(records, std::string("--size 64 --block 8 --assoc 2 --l2-size 128 --l2-block 16 "
                                               "--l2-assoc 2 ") + options);
    ASSERT_EQ(rows.size(), 1u) << options;
    const bool retain = std::string(options).find("retain") != std::string::npos;
    // Each cache misses on both fetches of its block (retain: one load, kept for the frame).
    EXPECT_EQ(rows[0].at("misses"), retain ? "2" : "4") << options;
    EXPECT_EQ(rows[0].at("l2_refs"), retain ? "3" : "4") << options;
    // The L2's 16-byte blocks 0 and 1: a miss each, then hits.
    EXPECT_EQ(rows[0].at("l2_misses"), "2") << options;
  }
  const auto spanning = run(kSpanningInvalidation, "--size 64 --block 8 --assoc 2 --l2-size 256 --l2-block 8 --l2-assoc 2");
  ASSERT_EQ(spanning.size(), 1u);
  EXPECT_EQ(spanning[0].at("misses"), "3");
  EXPECT_EQ(spanning[0].at("l2_refs"), "3");
}

}  // namespace
}  // namespace nodetrace::cachesim
