// Report text: exact CSV and JSON, miss ratios from integer counts, tables.
#include <gtest/gtest.h>

#include "nodetrace/cachesim/report/report.hpp"

namespace nodetrace::cachesim {
namespace {

std::vector<ResultRow> sample_rows() {
  ResultRow single;
  single.trace = "kd.din.zst";
  single.config.scheme = Scheme::Single;
  single.config.size = 8192;
  single.config.block = 8;
  single.config.assoc = 1;
  single.refs = 200000;
  single.fetches = 200000;
  single.misses = 39930;

  ResultRow split = single;
  split.config.scheme = Scheme::Split;
  split.config.high_policy = HighPolicy::Retain;
  split.config.high_size = 4096;
  split.config.low_size = 4096;
  split.split_level = 9;
  split.misses = 30001;
  split.high_refs = 120000;
  split.high_misses = 0;
  split.high_loads = 511;
  split.low_refs = 80000;
  split.low_misses = 30001;

  ResultRow cache = split;
  cache.trace = "a,b";
  cache.config.high_policy = HighPolicy::Cache;
  cache.high_loads.reset();
  cache.high_misses = 7;
  cache.misses = 30008;
  return {single, split, cache};
}

TEST(Report, MissRatioHasSixDecimalsFromIntegerCounts) {
  EXPECT_EQ(miss_ratio_text(39930, 200000), "0.199650");
  EXPECT_EQ(miss_ratio_text(1, 3), "0.333333");
  EXPECT_EQ(miss_ratio_text(2, 3), "0.666667");
  EXPECT_EQ(miss_ratio_text(1, 2000000), "0.000001");  // half rounds up
  EXPECT_EQ(miss_ratio_text(5, 5), "1.000000");
  EXPECT_EQ(miss_ratio_text(0, 0), "");  // a ratio of no fetches is empty (null in JSON), never 0
  EXPECT_EQ(miss_ratio_text(~std::uint64_t{0} / 3, ~std::uint64_t{0}), "0.333333");
}

TEST(Report, CsvExactText) {
  EXPECT_EQ(format_rows(sample_rows(), ReportFormat::Csv),
            "trace,scheme,size,block,assoc,policy,high_policy,high_size,low_size,split_level,"
            "refs,fetches,misses,miss_ratio,high_refs,high_misses,high_loads,low_refs,low_misses\n"
            "kd.din.zst,single,8192,8,1,lru,,,,,200000,200000,39930,0.199650,,,,,\n"
            "kd.din.zst,split,8192,8,1,lru,retain,4096,4096,9,200000,200000,30001,0.150005,"
            "120000,0,511,80000,30001\n"
            "\"a,b\",split,8192,8,1,lru,cache,4096,4096,9,200000,200000,30008,0.150040,"
            "120000,7,,80000,30001\n");
}

TEST(Report, JsonExactText) {
  const std::vector<ResultRow> all = sample_rows();
  const std::vector<ResultRow> rows(all.begin(), all.begin() + 2);
  EXPECT_EQ(format_rows(rows, ReportFormat::Json),
            "{\"columns\": [\"trace\", \"scheme\", \"size\", \"block\", \"assoc\", \"policy\", "
            "\"high_policy\", \"high_size\", \"low_size\", \"split_level\", \"refs\", \"fetches\", "
            "\"misses\", \"miss_ratio\", \"high_refs\", \"high_misses\", \"high_loads\", \"low_refs\", "
            "\"low_misses\"],\n"
            " \"rows\": [\n"
            "  {\"trace\": \"kd.din.zst\", \"scheme\": \"single\", \"size\": 8192, \"block\": 8, "
            "\"assoc\": 1, \"policy\": \"lru\", \"high_policy\": null, \"high_size\": null, "
            "\"low_size\": null, \"split_level\": null, \"refs\": 200000, \"fetches\": 200000, "
            "\"misses\": 39930, \"miss_ratio\": 0.199650, \"high_refs\": null, "
            "\"high_misses\": null, \"high_loads\": null, \"low_refs\": null, "
            "\"low_misses\": null},\n"
            "  {\"trace\": \"kd.din.zst\", \"scheme\": \"split\", \"size\": 8192, \"block\": 8, "
            "\"assoc\": 1, \"policy\": \"lru\", \"high_policy\": \"retain\", \"high_size\": 4096, "
            "\"low_size\": 4096, \"split_level\": 9, \"refs\": 200000, \"fetches\": 200000, "
            "\"misses\": 30001, \"miss_ratio\": 0.150005, \"high_refs\": 120000, "
            "\"high_misses\": 0, \"high_loads\": 511, \"low_refs\": 80000, "
            "\"low_misses\": 30001}\n"
            "]}\n");
  const std::string empty = format_rows({}, ReportFormat::Json);
  EXPECT_EQ(empty.substr(0, 12), "{\"columns\": ");
  EXPECT_EQ(empty.substr(empty.size() - 13), " \"rows\": []}\n");
}

TEST(Report, NoFetchesGiveAnEmptyMissRatioNotZero) {
  ResultRow none;
  none.trace = "empty.din";
  const std::string csv = format_rows({none}, ReportFormat::Csv);
  EXPECT_NE(csv.find("\nempty.din,single,8192,8,1,lru,,,,,0,0,0,,,,,,\n"), std::string::npos) << csv;
  EXPECT_NE(format_rows({none}, ReportFormat::Json).find("\"miss_ratio\": null"), std::string::npos);
}

TEST(Report, FullyAssociativeCachesReadFull) {
  ResultRow full = sample_rows().front();
  full.config.assoc = 1024;  // 8192 / 8: one set
  ResultRow split = sample_rows()[1];
  split.config.assoc = 512;  // the low cache's 4096 / 8
  const std::string csv = format_rows({full, split}, ReportFormat::Csv);
  EXPECT_NE(csv.find("kd.din.zst,single,8192,8,full,lru,"), std::string::npos) << csv;
  EXPECT_NE(csv.find("kd.din.zst,split,8192,8,full,lru,"), std::string::npos) << csv;
  EXPECT_NE(format_rows({full}, ReportFormat::Json).find("\"assoc\": \"full\""), std::string::npos);
}

TEST(Report, TableAlignsColumns) {
  const std::string table = format_rows(sample_rows(), ReportFormat::Table);
  std::vector<std::string> lines;
  std::size_t start = 0;
  while (start < table.size()) {
    const std::size_t end = table.find('\n', start);
    lines.push_back(table.substr(start, end - start));
    start = end + 1;
  }
  ASSERT_EQ(lines.size(), 4u);
  // Every number column ends at the same place on every line: miss_ratio.
  const std::size_t ratio_end = lines[0].find("miss_ratio") + std::string("miss_ratio").size();
  EXPECT_EQ(lines[1].substr(ratio_end - 8, 8), "0.199650");
  EXPECT_EQ(lines[2].substr(ratio_end - 8, 8), "0.150005");
  EXPECT_NE(lines[1].find("single"), std::string::npos);
  EXPECT_NE(lines[1].find(" - "), std::string::npos);  // empty columns shown as -
}

TEST(Report, PerLevelRowsCarryEveryConfigurationColumn) {
  LevelRow direct{"kd.din.zst", sample_rows()[1].config, 9, 3, 100, 7};
  LevelRow cache = direct;
  cache.config.assoc = 4;
  cache.config.high_policy = HighPolicy::Cache;
  cache.misses = 2;
  EXPECT_EQ(format_level_rows({direct, cache}, ReportFormat::Csv),
            "trace,scheme,size,block,assoc,policy,high_policy,high_size,low_size,split_level,level,refs,misses\n"
            "kd.din.zst,split,8192,8,1,lru,retain,4096,4096,9,3,100,7\n"
            "kd.din.zst,split,8192,8,4,lru,cache,4096,4096,9,3,100,2\n");
  const std::string json = format_level_rows({direct}, ReportFormat::Json);
  EXPECT_NE(json.find("{\"trace\": \"kd.din.zst\", \"scheme\": \"split\", \"size\": 8192, \"block\": 8, "
                      "\"assoc\": 1, \"policy\": \"lru\", \"high_policy\": \"retain\", \"high_size\": 4096, "
                      "\"low_size\": 4096, \"split_level\": 9, \"level\": 3, \"refs\": 100, \"misses\": 7}"),
            std::string::npos)
      << json;
}

}  // namespace
}  // namespace nodetrace::cachesim
