// TagFilter: levels, ranges, p and t, and the usage errors that name the option.
#include <gtest/gtest.h>

#include "nodetrace/base/error.hpp"
#include "nodetrace/formats/record/tag_filter.hpp"

namespace nodetrace::formats {
namespace {

TEST(TagFilter, KeepsLevelsRangesAndTheOtherStreams) {
  const TagFilter filter = TagFilter::parse("0-3,9-,p");
  for (const Tag level : {0, 1, 3, 9, 10, 100}) EXPECT_TRUE(filter.keeps(level)) << level;
  EXPECT_TRUE(filter.keeps(kMaxLevel));
  for (const Tag level : {4, 5, 8}) EXPECT_FALSE(filter.keeps(level)) << level;
  EXPECT_TRUE(filter.keeps(kTagPrimitiveList));
  EXPECT_FALSE(filter.keeps(kTagTriangle));
  EXPECT_FALSE(filter.keeps(kTagNone));
  const TagFilter single = TagFilter::parse("7,t");
  EXPECT_TRUE(single.keeps(7));
  EXPECT_FALSE(single.keeps(6));
  EXPECT_TRUE(single.keeps(kTagTriangle));
}

TEST(TagFilter, BadItemsAreUsageErrorsNamingTheOption) {
  for (const char* text : {"", "x", "1-x", "3-1", "65521", "0-3,,p", "-2"}) {
    try {
      TagFilter::parse(text, "--keep");
      ADD_FAILURE() << "'" << text << "' was accepted";
    } catch (const base::UsageError& error) {
      EXPECT_EQ(std::string(error.what()).rfind("--keep: ", 0), 0u) << error.what();
    }
  }
}

}  // namespace
}  // namespace nodetrace::formats
