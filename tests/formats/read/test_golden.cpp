// The Dinero IV golden traces in ../shared/dinero-golden read to their exact
// record counts and histograms.
#include <gtest/gtest.h>

#include <array>
#include <map>
#include <numeric>

#include "formats_test_util.hpp"
#include "test_support.hpp"

namespace nodetrace::formats {
namespace {

using testing_util::read_all;

std::array<std::uint64_t, kAccessTypeCount> type_histogram(const std::vector<Record>& records) {
  std::array<std::uint64_t, kAccessTypeCount> counts{};
  for (const auto& record : records) ++counts[static_cast<std::size_t>(record.type)];
  return counts;
}

TEST(Golden, Mm32DinReadsExactly) {
  NODETRACE_SHARED_OR_SKIP(shared);
  const auto result = read_all((shared / "dinero-golden" / "mm32.din.zst").string());
  EXPECT_EQ(result.form, RecordForm::Din);
  EXPECT_FALSE(result.tags_are_levels);
  ASSERT_EQ(result.records.size(), 265775u);
  const auto counts = type_histogram(result.records);
  EXPECT_EQ(counts[0], 70370u);
  EXPECT_EQ(counts[1], 6426u);
  EXPECT_EQ(counts[2], 188971u);
  EXPECT_EQ(counts[3], 8u);
  EXPECT_EQ(counts[4] + counts[5], 0u);
  EXPECT_EQ(result.records[0], (Record{0x130, 4, AccessType::InstructionFetch, TraversalUnit{}, kTagNone}));
  EXPECT_EQ(result.records[2], (Record{0xff2f80, 4, AccessType::Read, TraversalUnit{}, kTagNone}));
  std::uint64_t address_sum = 0;
  for (const auto& record : result.records) address_sum += record.address;
  EXPECT_EQ(address_sum, 370683768704u);
}

TEST(Golden, Mm32ExtendedDinReadsExactly) {
  NODETRACE_SHARED_OR_SKIP(shared);
  const auto result = read_all((shared / "dinero-golden" / "mm32.xdin.zst").string());
  EXPECT_EQ(result.form, RecordForm::ExtendedDin);
  ASSERT_EQ(result.records.size(), 265775u);
  const auto counts = type_histogram(result.records);
  EXPECT_EQ(counts[0], 70370u);
  EXPECT_EQ(counts[1], 6426u);
  EXPECT_EQ(counts[2], 188971u);
  EXPECT_EQ(counts[3], 8u);
  std::map<std::uint32_t, std::uint64_t> sizes;
  for (const auto& record : result.records) ++sizes[record.size];
  EXPECT_EQ(sizes, (std::map<std::uint32_t, std::uint64_t>{{1, 65}, {4, 189360}, {8, 76350}}));
  // Same references as the din trace, apart from sizes.
  const auto din = read_all((shared / "dinero-golden" / "mm32.din.zst").string());
  for (std::size_t i = 0; i < din.records.size(); i += 997) {
    EXPECT_EQ(din.records[i].address, result.records[i].address);
    EXPECT_EQ(din.records[i].type, result.records[i].type);
  }
}

TEST(Golden, KdTraceLevelsReadExactly) {
  NODETRACE_SHARED_OR_SKIP(shared);
  const std::string file = (shared / "dinero-golden" / "kd-bfl-s1.din.zst").string();
  // A plain zstd trace: its tags are levels only when told.
  const auto untagged = read_all(file);
  ASSERT_EQ(untagged.records.size(), 200000u);
  EXPECT_EQ(untagged.records[1].tag, kTagNone);
  ReaderOptions levels;
  levels.tags_are_levels = true;
  const auto result = read_all(file, levels);
  ASSERT_EQ(result.records.size(), 200000u);
  EXPECT_EQ(type_histogram(result.records)[0], 200000u);
  const std::vector<std::uint64_t> expected = {16923, 17548, 18510, 19920, 19740, 14343, 15687, 11184, 11294,
                                               10916, 9682,  8650,  6538,  5465,  4502,  3127,  2286,  1507,
                                               891,   575,   350,   210,   99,    36,    12,    5};
  std::vector<std::uint64_t> per_level(expected.size(), 0);
  for (const auto& record : result.records) {
    ASSERT_LT(record.tag, per_level.size());
    ++per_level[record.tag];
  }
  EXPECT_EQ(per_level, expected);
  EXPECT_EQ(result.records[1], (Record{0x10000010, 4, AccessType::Read, TraversalUnit{}, 1}));
  std::uint64_t address_sum = 0;
  for (const auto& record : result.records) address_sum += record.address;
  EXPECT_EQ(address_sum, 53688366752896u);
}

TEST(Golden, KdTraceConvertsToALevelContainerThatZstdcatReproduces) {
  NODETRACE_SHARED_OR_SKIP(shared);
  nodetrace::testing::TempDir dir;
  const std::string file = (shared / "dinero-golden" / "kd-bfl-s1.din.zst").string();
  ReaderOptions levels;
  levels.tags_are_levels = true;
  const auto original = read_all(file, levels);
  WriterOptions options;
  options.records_per_data_frame = 30000;
  testing_util::write_trace((dir / "kd.din.zst").string(), original.records, options);
  const auto back = read_all((dir / "kd.din.zst").string());
  EXPECT_TRUE(back.tags_are_levels);
  EXPECT_EQ(back.records, original.records);
  const auto text = nodetrace::testing::run_command("zstd -dc '" + (dir / "kd.din.zst").string() + "'");
  ASSERT_EQ(text.exit_code, 0);
  EXPECT_EQ(text.out.substr(0, 28), "0 10000000 00\n0 10000010 01\n");
  EXPECT_EQ(std::count(text.out.begin(), text.out.end(), '\n'), 200000);
}

}  // namespace
}  // namespace nodetrace::formats
