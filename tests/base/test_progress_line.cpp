// The progress line's text: count, total, percent, rate and time left when
// the total is known (issue 22 item 15), the count and rate when it is not.
#include <gtest/gtest.h>

#include "nodetrace/cli/progress_line.hpp"

namespace nodetrace::cli {
namespace {

TEST(ProgressText, KnownTotalShowsPercentRateAndTimeLeft) {
  EXPECT_EQ(progress_text("t.din.zst", 18'000'000, 75'600'000, "records", 2.0),
            "t.din.zst: 18.0 M of 75.6 M records (23%), 9.0 M records/s, 7 s left");
  EXPECT_EQ(progress_text("robot", 30'000, 480'000, "pixels", 10.0),
            "robot: 30000 of 480000 pixels (6%), 3000 pixels/s, 2:30 min left");
}

TEST(ProgressText, UnknownTotalShowsCountAndRate) {
  EXPECT_EQ(progress_text("<stdin>", 18'000'000, std::nullopt, "records", 3.0),
            "<stdin>: 18.0 M records, 6.0 M records/s");
}

TEST(ProgressText, NoRateBeforeTimePasses) {
  EXPECT_EQ(progress_text("t", 0, 100, "records", 0.0), "t: 0 of 100 records (0%)");
  EXPECT_EQ(progress_text("t", 100, 100, "records", 1.0), "t: 100 of 100 records (100%), 100 records/s");
}

// tracer's first estimate said "1:04 min left" for a 2-second render: the
// time left waits for a second and 5% of the work (issue 34 item 18).
TEST(ProgressText, NoTimeLeftBeforeEnoughWorkIsTimed) {
  EXPECT_EQ(progress_text("r", 600, 30'000, "pixels", 0.5), "r: 600 of 30000 pixels (2%), 1200 pixels/s");
  EXPECT_EQ(progress_text("r", 600, 30'000, "pixels", 3.0), "r: 600 of 30000 pixels (2%), 200 pixels/s");
  EXPECT_EQ(progress_text("r", 6'000, 30'000, "pixels", 0.5), "r: 6000 of 30000 pixels (20%), 12000 pixels/s");
  EXPECT_EQ(progress_text("r", 1'500, 30'000, "pixels", 1.0),
            "r: 1500 of 30000 pixels (5%), 1500 pixels/s, 19 s left");
}

}  // namespace
}  // namespace nodetrace::cli
