// RecordSummary: counts by tag and type with the trailer's keys, and the
// reading order of tag keys; the writer's trailer totals are one.
#include <gtest/gtest.h>

#include "formats_test_util.hpp"
#include "nodetrace/formats/record/record_summary.hpp"
#include "test_support.hpp"

namespace nodetrace::formats {
namespace {

TEST(RecordSummary, CountsByTagAndTypeWithTheTrailersKeys) {
  RecordSummary summary;
  summary.add(Record{0x10, 4, AccessType::Read, TraversalUnit{}, 2});
  summary.add(std::vector<Record>{{0x20, 4, AccessType::Write, TraversalUnit{}, 2},
                                  {0x30, 4, AccessType::Read, TraversalUnit{}, kTagPrimitiveList},
                                  {0x40, 4, AccessType::Invalidate, TraversalUnit{}, kTagNone},
                                  {0x50, 4, AccessType::Read, TraversalUnit{}, 12}});
  EXPECT_EQ(summary.records(), 5u);
  EXPECT_EQ(summary.records_per_tag().dump(), R"({"12":1,"2":2,"none":1,"p":1})");
  EXPECT_EQ(summary.records_per_type().dump(),
            R"({"copy_back":0,"instruction_fetch":0,"invalidate":1,"misc":0,"read":3,"write":1})");
  const auto rows = ordered_tag_counts(summary.records_per_tag());
  ASSERT_EQ(rows.size(), 4u);
  EXPECT_EQ(rows[0].first, "2");
  EXPECT_EQ(rows[1].first, "12");
  EXPECT_EQ(rows[2].first, "p");
  EXPECT_EQ(rows[3].first, "none");
  EXPECT_EQ(access_type_name(AccessType::CopyBack), "copy_back");
  EXPECT_EQ(tag_key(kTagTriangle), "t");
}

TEST(RecordSummary, IsWhatTheWriterPutsInTheTrailer) {
  nodetrace::testing::TempDir dir;
  const auto records = testing_util::sample_records(5000);
  WriterOptions options;
  options.records_per_data_frame = 700;
  testing_util::write_trace((dir / "t.din.zst").string(), records, options);
  RecordSummary summary;
  summary.add(records);
  const auto reader = TraceReader::open((dir / "t.din.zst").string());
  EXPECT_EQ(reader->trailer()->totals.at("records_per_tag"), summary.records_per_tag());
  EXPECT_EQ(reader->trailer()->totals.at("records_per_type"), summary.records_per_type());
}

}  // namespace
}  // namespace nodetrace::formats
