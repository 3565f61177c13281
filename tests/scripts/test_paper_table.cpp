// scripts/paper-table1.csv, the project's cited copy of the paper's Table 1,
// holds exactly the 18 values of ../shared/paper/table1.csv, and its
// direction column says what those values say.
#include <gtest/gtest.h>

#include <map>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "test_support.hpp"

namespace nodetrace::testing {
namespace {

// The data lines of a CSV file (no '#' comments), split at commas, header first.
std::vector<std::vector<std::string>> csv_rows(const std::filesystem::path& path) {
  std::istringstream lines(read_file(path));
  std::vector<std::vector<std::string>> rows;
  for (std::string line; std::getline(lines, line);) {
    if (line.empty() || line[0] == '#') continue;
    std::vector<std::string> fields;
    std::istringstream cells(line);
    for (std::string cell; std::getline(cells, cell, ',');) fields.push_back(cell);
    rows.push_back(fields);
  }
  return rows;
}

std::size_t column(const std::vector<std::string>& header, const std::string& name) {
  for (std::size_t i = 0; i < header.size(); ++i) {
    if (header[i] == name) return i;
  }
  ADD_FAILURE() << "no column " << name;
  return 0;
}

// (paper scene, size as "4KB") -> (without, with), as written.
using Table = std::map<std::pair<std::string, std::string>, std::pair<std::string, std::string>>;

TEST(PaperTable, ProjectFileHoldsExactlyTheEighteenValuesOfTheSharedCopy) {
  NODETRACE_SHARED_OR_SKIP(shared);
  const auto theirs_rows = csv_rows(shared / "paper" / "table1.csv");
  const auto ours_rows = csv_rows(std::filesystem::path(NODETRACE_SOURCE_DIR) / "scripts" / "paper-table1.csv");
  ASSERT_FALSE(theirs_rows.empty());
  ASSERT_FALSE(ours_rows.empty());

  Table theirs, ours;
  {
    const auto& h = theirs_rows[0];
    const auto scene = column(h, "scene"), size = column(h, "size"), without = column(h, "without_percent"),
               with = column(h, "with_percent");
    for (std::size_t r = 1; r < theirs_rows.size(); ++r) {
      const auto& row = theirs_rows[r];
      theirs[{row[scene], row[size]}] = {row[without], row[with]};
    }
  }
  {
    const auto& h = ours_rows[0];
    const auto scene = column(h, "paper_scene"), size = column(h, "size"), without = column(h, "without_percent"),
               with = column(h, "with_percent"), better = column(h, "better");
    for (std::size_t r = 1; r < ours_rows.size(); ++r) {
      const auto& row = ours_rows[r];
      ASSERT_EQ(row.size(), h.size()) << "row " << r;
      std::string label = row[size];  // "4k" -> "4KB", as the paper writes it
      ASSERT_FALSE(label.empty());
      label = label.substr(0, label.size() - 1) + "KB";
      EXPECT_TRUE(ours.emplace(std::pair{row[scene], label}, std::pair{row[without], row[with]}).second)
          << row[scene] << " " << label << " twice";
      // The direction column is what the two values say.
      const double single = std::stod(row[without]), split = std::stod(row[with]);
      EXPECT_EQ(row[better], split < single ? "split" : "single") << row[scene] << " " << label;
    }
  }
  EXPECT_EQ(theirs.size(), 9u);
  EXPECT_EQ(ours.size(), 9u);
  for (const auto& [cell, values] : theirs) {
    const auto found = ours.find(cell);
    ASSERT_NE(found, ours.end()) << cell.first << " " << cell.second << " missing";
    // Compared as numbers: 10.70 and 10.7 are the same value.
    EXPECT_DOUBLE_EQ(std::stod(found->second.first), std::stod(values.first)) << cell.first << " " << cell.second;
    EXPECT_DOUBLE_EQ(std::stod(found->second.second), std::stod(values.second)) << cell.first << " " << cell.second;
  }
}

}  // namespace
}  // namespace nodetrace::testing
