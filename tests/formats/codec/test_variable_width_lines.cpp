// The fast path for text lines of other tools (fields of any width) gives the
// general parser's records and errors: every text is parsed once as it is and
// once with each line behind a leading blank, which only the general parser
// takes, and the two must agree, for common lines and for every byte of them
// changed. Internal: the codec is tested directly (formats/src).
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <random>
#include <string>
#include <vector>

#include "codec/record_codec.hpp"
#include "codec/variable_width_lines.hpp"

namespace nodetrace::formats {
namespace {


struct Outcome {
  bool ok = false;
  std::vector<Record> records;
  detail::RecordError error;
  std::uint64_t ignored_fields = 0;
};

Outcome parse(const std::string& text, RecordForm form, bool tags) {
  detail::ParseSettings settings;
  settings.form = form;
  settings.tags_are_levels = tags;
  Outcome outcome;
  outcome.ok = detail::parse_records(text, settings, outcome.records, outcome.error, outcome.ignored_fields);
  return outcome;
}

// Each line of `text` behind a blank: the general parser reads every one.
std::string behind_blanks(const std::string& text) {
  std::string out;
  bool line_start = true;
  for (const char c : text) {
    if (line_start) out += ' ';
    out += c;
    line_start = c == '\n';
  }
  return out;
}

void expect_same_as_general(const std::string& text, RecordForm form, bool tags) {
  const Outcome fast = parse(text, form, tags);
  const Outcome general = parse(behind_blanks(text), form, tags);
  EXPECT_EQ(fast.ok, general.ok) << "text:\n" << text;
  EXPECT_EQ(fast.error.message, general.error.message) << "text:\n" << text;
  EXPECT_EQ(fast.error.record_in_chunk, general.error.record_in_chunk) << "text:\n" << text;
  EXPECT_EQ(fast.records, general.records) << "text:\n" << text;
  EXPECT_EQ(fast.ignored_fields, general.ignored_fields) << "text:\n" << text;
}

const std::vector<std::string> kDinLines = {"0 100 3", "2 0x1a2b 07", "1 ffffffffffffffff 12", "4 abc p",
                                            "5 7fff t", "3 0 65520", "0\t12\t3", "1 00001a38 05", "0 0X10 0"};
const std::vector<std::string> kXdinLines = {"r 100 4 3", "w 0x10 8 07", "i 1 ffff 2", "v 1234 1 p",
                                             "m\tabc\t10\t3", "c ffffffffffffffff 0x40 t", "r 00001a38 8 05"};

std::string untagged(const std::string& line) { return line.substr(0, line.find_last_of(" \t")); }

TEST(VariableWidthLines, CommonLinesGiveTheGeneralParsersRecords) {
  for (const bool tags : {false, true}) {
    for (const RecordForm form : {RecordForm::Din, RecordForm::ExtendedDin}) {
      std::string text;
      for (const std::string& line : form == RecordForm::Din ? kDinLines : kXdinLines) {
        text += (tags ? line : untagged(line)) + "\n";
        if (!tags) text += line + "\n";  // a tag that is not a level: ignored, and counted
      }
      EXPECT_TRUE(parse(text, form, tags).ok);
      expect_same_as_general(text, form, tags);
    }
  }
}

// Agreement with the general parser cannot show that the fast path takes a
// line at all (the general parser reads what it leaves): it is called here
// alone, and must take every common line.
TEST(VariableWidthLines, TheFastPathItselfTakesEveryCommonLine) {
  for (const bool tags : {false, true}) {
    for (const RecordForm form : {RecordForm::Din, RecordForm::ExtendedDin}) {
      const std::vector<std::string>& lines = form == RecordForm::Din ? kDinLines : kXdinLines;
      std::string text;
      for (int copy = 0; copy < 20; ++copy) {
        for (const std::string& line : lines) text += (tags ? line : untagged(line)) + "\n";
      }
      std::vector<Record> records;
      std::uint64_t ignored = 0;
      const std::size_t taken =
          form == RecordForm::Din
              ? detail::variable_width_lines<false>(text.data(), text.data() + text.size(), tags, records, ignored)
              : detail::variable_width_lines<true>(text.data(), text.data() + text.size(), tags, records, ignored);
      EXPECT_EQ(taken, text.size()) << "tags " << tags << ", extended " << (form == RecordForm::ExtendedDin);
      EXPECT_EQ(records.size(), 20 * lines.size());
      EXPECT_EQ(ignored, 0u);
      EXPECT_EQ(records, parse(text, form, tags).records);
    }
  }
}

TEST(VariableWidthLines, RandomLinesOfEveryWidthGiveTheGeneralParsersRecords) {
  std::mt19937_64 random(11);
  for (const bool tags : {false, true}) {
    for (const RecordForm form : {RecordForm::Din, RecordForm::ExtendedDin}) {
      std::string text;
      for (int i = 0; i < 5000; ++i) {
        const std::uint64_t address = random() >> (random() % 64);
        const char blank = random() % 5 == 0 ? '\t' : ' ';
        std::string line = form == RecordForm::Din ? std::to_string(random() % 6) : std::string(1, "rwimcv"[random() % 6]);
        line += blank;
        line += random() % 4 == 0 ? fmt::format("0x{:x}", address) : fmt::format("{:0{}x}", address, random() % 12);
        if (form == RecordForm::ExtendedDin) line += fmt::format("{}{:x}", blank, 1 + random() % 0xFFFF);
        const auto tag = random() % 10;
        if (tags || tag < 3) line += tag == 0 ? " p" : tag == 1 ? " t" : fmt::format(" {}", random() % 70000);
        text += line + "\n";
      }
      expect_same_as_general(text, form, tags);
    }
  }
}

TEST(VariableWidthLines, EveryByteOfALineChangedGivesTheGeneralParsersRecordOrError) {
  const std::string replacements = std::string(" \t\r0589afgxXpt-rwv+") + '\x80' + '\0';
  for (const bool tags : {false, true}) {
    for (const RecordForm form : {RecordForm::Din, RecordForm::ExtendedDin}) {
      const std::string valid = form == RecordForm::Din ? "0 10 01\n" : "r 10 8 01\n";
      for (const std::string& base : form == RecordForm::Din ? kDinLines : kXdinLines) {
        for (std::size_t at = 0; at < base.size(); ++at) {
          std::vector<std::string> changed;
          for (const char c : replacements) changed.push_back(base.substr(0, at) + c + base.substr(at + 1));
          changed.push_back(base.substr(0, at) + base.substr(at + 1));   // the byte removed
          changed.push_back(base.substr(0, at) + " " + base.substr(at));  // a blank inserted
          changed.push_back(base.substr(0, at));                           // the line cut short
          for (const std::string& line : changed) {
            expect_same_as_general(valid + line + "\n" + valid, form, tags);
            if (::testing::Test::HasFailure()) return;
          }
        }
      }
    }
  }
}

}  // namespace
}  // namespace nodetrace::formats
