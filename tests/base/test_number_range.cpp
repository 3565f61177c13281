// cli::NumberRange: a value that is not a number says so, one outside the
// range says that, each with the option CLI11 puts in front; --help shows
// the range as CLI11's Range did.
#include <gtest/gtest.h>

#include <CLI/CLI.hpp>

#include <cstdint>
#include <string>

#include "nodetrace/cli/number_range.hpp"

namespace nodetrace::cli {
namespace {

// The message parsing `--n VALUE` gives, empty when it is accepted.
template <typename T>
std::string parse_error(T min, T max, const std::string& value) {
  CLI::App app;
  T bound{};
  app.add_option("--n", bound)->check(NumberRange(min, max));
  try {
    app.parse(std::vector<std::string>{value, "--n"});  // reversed: CLI11 takes the last first
  } catch (const CLI::ParseError& error) {
    return error.what();
  }
  return {};
}

TEST(NumberRange, SaysWhetherAValueIsNotANumberOrOutsideTheRange) {
  EXPECT_EQ(parse_error(1u, 65536u, "abc"), "--n: 'abc' is not a whole number: expected 1 to 65536");
  EXPECT_EQ(parse_error(1u, 65536u, "1.5"), "--n: '1.5' is not a whole number: expected 1 to 65536");
  EXPECT_EQ(parse_error(1u, 65536u, "0"), "--n: 0 is outside 1 to 65536");
  EXPECT_EQ(parse_error(1u, 65536u, "-1"), "--n: -1 is outside 1 to 65536");
  EXPECT_EQ(parse_error(1u, 65536u, "99999999999"), "--n: 99999999999 is outside 1 to 65536");
  EXPECT_EQ(parse_error(1u, 65536u, "65536"), "");
  EXPECT_EQ(parse_error(-7, 22, "-7"), "");
  EXPECT_EQ(parse_error(0.0f, 1.0f, "abc"), "--n: 'abc' is not a number: expected 0 to 1");
  EXPECT_EQ(parse_error(0.0f, 1.0f, "nan"), "--n: 'nan' is not a number: expected 0 to 1");
  EXPECT_EQ(parse_error(0.0f, 1.0f, "1.5"), "--n: 1.5 is outside 0 to 1");
  EXPECT_EQ(parse_error(0.0f, 1.0f, "0.25"), "");
}

TEST(NumberRange, HelpShowsTheRangeAsCli11sRangeDid) {
  EXPECT_EQ(NumberRange(1u, 65536u).get_description(), CLI::Range(1u, 65536u).get_description());
  EXPECT_EQ(NumberRange(-7, 22).get_description(), CLI::Range(-7, 22).get_description());
}

}  // namespace
}  // namespace nodetrace::cli
