// The readings of "the high-level node cache and the low-level node cache
// have same size" that the interpretations study compares: a row's size as
// the total split half and half, or as each cache's size. Each cache the
// row's size at 4 KB is the half-and-half split of 8 KB: the same counts.
#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <vector>

#include "test_support.hpp"

namespace nodetrace {
namespace {

// cachesim's CSV rows as name -> value maps.
std::vector<std::vector<std::pair<std::string, std::string>>> csv_rows(const std::string& text) {
  std::istringstream lines(text);
  std::string line;
  std::getline(lines, line);
  std::vector<std::string> names;
  std::istringstream header(line);
  for (std::string name; std::getline(header, name, ',');) names.push_back(name);
  std::vector<std::vector<std::pair<std::string, std::string>>> rows;
  while (std::getline(lines, line) && !line.empty()) {
    std::istringstream cells(line);
    std::vector<std::pair<std::string, std::string>> row;
    std::string cell;
    for (const auto& name : names) {
      std::getline(cells, cell, ',');
      row.emplace_back(name, cell);
    }
    rows.push_back(row);
  }
  return rows;
}

std::string value(const std::vector<std::pair<std::string, std::string>>& row, const std::string& name) {
  for (const auto& [key, cell] : row) {
    if (key == name) return cell;
  }
  ADD_FAILURE() << "no column " << name;
  return {};
}

TEST(SizeInterpretations, EachCacheTheRowsSizeAt4KIsTheHalfAndHalfSplitAt8K) {
  testing::TempDir dir;
  const auto trace = dir / "render.din.zst";
  // The high cache of 4 KB is what the layout's K is sized for in both readings.
  const auto rendered = testing::run_command(testing::shell_quoted(testing::program("tracer")) +
                                             " render mountain --width 32 --height 24 --high-size 4k -q -o " +
                                             testing::shell_quoted(trace));
  ASSERT_EQ(rendered.exit_code, 0) << rendered.err;
  const std::string cachesim = testing::shell_quoted(testing::program("cachesim")) + " run " +
                               testing::shell_quoted(trace) +
                               " --block 8 --assoc 1 --scheme single,split --split-level auto --format csv ";
  const auto each = testing::run_command(cachesim + "--size 4k --high-size 4k --low-size 4k");
  const auto half = testing::run_command(cachesim + "--size 8k");
  ASSERT_EQ(each.exit_code, 0) << each.err;
  ASSERT_EQ(half.exit_code, 0) << half.err;
  const auto each_rows = csv_rows(each.out), half_rows = csv_rows(half.out);
  ASSERT_EQ(each_rows.size(), 2u) << each.out;
  ASSERT_EQ(half_rows.size(), 2u) << half.out;
  // Row 0 is the single cache: the row's size, 4 KB, against 8 KB.
  EXPECT_EQ(value(each_rows[0], "scheme"), "single");
  EXPECT_EQ(value(each_rows[0], "size"), "4096");
  EXPECT_EQ(value(half_rows[0], "size"), "8192");
  // Row 1 is the split: the same caches, so the same counts.
  const auto& a = each_rows[1];
  const auto& b = half_rows[1];
  EXPECT_EQ(value(a, "scheme"), "split");
  for (const std::string column : {"size", "high_size", "low_size", "split_level", "fetches", "misses",
                                   "high_refs", "high_misses", "high_loads", "low_refs", "low_misses"}) {
    EXPECT_EQ(value(a, column), value(b, column)) << column;
  }
  EXPECT_EQ(value(a, "high_size"), "4096");
  EXPECT_EQ(value(a, "low_size"), "4096");
  EXPECT_NE(value(a, "misses"), "0");
}

}  // namespace
}  // namespace nodetrace
