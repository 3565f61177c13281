#include <gtest/gtest.h>

#include "nodetrace/base/byte_size.hpp"
#include "nodetrace/base/error.hpp"

namespace nodetrace::base {
namespace {

TEST(ByteSize, ReadsPlainAndSuffixedSizes) {
  EXPECT_EQ(parse_byte_size("512"), 512u);
  EXPECT_EQ(parse_byte_size("8k"), 8192u);
  EXPECT_EQ(parse_byte_size("4K"), 4096u);
  EXPECT_EQ(parse_byte_size("1M"), 1048576u);
  EXPECT_EQ(parse_byte_size("2g"), 2147483648u);
}

TEST(ByteSize, RejectsWhatIsNotAPositiveSize) {
  for (const char* text : {"", "0", "k", "8q", "8kb", "-1", "4 k", "0x10", "1.5k",
                           "99999999999999999999", "17179869184g"}) {
    EXPECT_THROW(parse_byte_size(text), UsageError) << text;
  }
  try {
    parse_byte_size("8q");
    FAIL() << "no error";
  } catch (const UsageError& error) {
    EXPECT_STREQ(error.what(),
                 "'8q' is not a size: expected a positive number of bytes, optionally with k, m "
                 "or g (e.g. 8k)");
  }
}

}  // namespace
}  // namespace nodetrace::base
