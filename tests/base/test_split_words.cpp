// tracer render --simulate "OPTIONS": the text split into words as a shell
// splits it, quotes kept together and removed.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "nodetrace/base/error.hpp"
#include "nodetrace/cli/split_words.hpp"

namespace nodetrace::cli {
namespace {

using Words = std::vector<std::string>;

TEST(SplitWords, BlanksSeparateWords) {
  EXPECT_EQ(split_words("  --size 4k,8k\t--format  csv \n", "--simulate"),
            (Words{"--size", "4k,8k", "--format", "csv"}));
  EXPECT_EQ(split_words("", "--simulate"), Words{});
  EXPECT_EQ(split_words("   ", "--simulate"), Words{});
}

TEST(SplitWords, QuotesKeepBlanksAndGoAway) {
  EXPECT_EQ(split_words("--per-level 'my table.csv' --per-frame \"a b\".csv", "--simulate"),
            (Words{"--per-level", "my table.csv", "--per-frame", "a b.csv"}));
  EXPECT_EQ(split_words("'' x", "--simulate"), (Words{"", "x"}));
  EXPECT_EQ(split_words(R"("say \"hi\" \\ \n" 'it''s')", "--simulate"), (Words{R"(say "hi" \ \n)", "its"}));
  EXPECT_EQ(split_words(R"(a\ b \'c)", "--simulate"), (Words{"a b", "'c"}));
}

TEST(SplitWords, OpenQuoteOrTrailingBackslashIsAUsageError) {
  try {
    split_words("--per-level 'x", "--simulate");
    FAIL() << "an open quote was accepted";
  } catch (const base::UsageError& error) {
    EXPECT_STREQ(error.what(), "--simulate: '--per-level 'x': the quote ' at character 13 is not closed");
  }
  EXPECT_THROW(split_words("--size 4k\\", "--simulate"), base::UsageError);
}

}  // namespace
}  // namespace nodetrace::cli
