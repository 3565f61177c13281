// Din / extended din / binary parsing: docs/ARCHITECTURE.md's table of what Dinero IV
// accepts, and one clear error for every other class of malformed input.
#include <gtest/gtest.h>

#include <cstdio>

#include <fmt/format.h>

#include "formats_test_util.hpp"
#include "test_support.hpp"

namespace nodetrace::formats {
namespace {

using testing_util::read_all;
using testing_util::read_error;
using testing_util::with_stdin_from;
using testing_util::write_trace;

std::string line(const char* format, unsigned address, int level) {
  char text[64];
  std::snprintf(text, sizeof text, format, address, level);
  return text;
}

class TextParsing : public ::testing::Test {
 protected:
  std::string write(const std::string& text, const std::string& name = "t.din") {
    const auto path = dir_ / name;
    nodetrace::testing::write_file(path, text);
    return path.string();
  }
  std::string error_of(const std::string& text, ReaderOptions options = {}) {
    return read_error(write(text), options);
  }
  nodetrace::testing::TempDir dir_;
};

TEST_F(TextParsing, AcceptsEveryDinLayoutDineroAccepts) {
  const auto result = read_all(write("0 100\n0x0 100\n0 0x100\n00 100\n  0\t100\n0 100 5 extra\n"
                                     "4 10\n5 20\n2 13c\n0 ffffffffffffffff\n0 000000000000000000001\n"));
  ASSERT_EQ(result.records.size(), 11u);
  EXPECT_EQ(result.form, RecordForm::Din);
  for (int i = 0; i < 6; ++i) {
    EXPECT_EQ(result.records[i].address, 0x100u) << i;
    EXPECT_EQ(result.records[i].type, AccessType::Read) << i;
    EXPECT_EQ(result.records[i].size, 4u);
    EXPECT_EQ(result.records[i].tag, kTagNone);
  }
  EXPECT_EQ(result.records[6].type, AccessType::CopyBack);
  EXPECT_EQ(result.records[7].type, AccessType::Invalidate);
  EXPECT_EQ(result.records[8].type, AccessType::InstructionFetch);
  EXPECT_EQ(result.records[8].address, 0x13cu);
  EXPECT_EQ(result.records[9].address, ~std::uint64_t{0});
  EXPECT_EQ(result.records[10].address, 1u);
}

TEST_F(TextParsing, LastLineWithoutNewlineIsARecord) {
  EXPECT_EQ(read_all(write("0 100\n1 200")).records.size(), 2u);
}

// One rule for every input without records, file or pipe, plain, zstd or
// container: refused (exit 1 in the programs), except where Dinero IV's
// reading of it is followed (allow_empty: cachesim dinero, dinero-wrap exec).
TEST_F(TextParsing, AnInputWithoutRecordsIsRefusedUnlessAllowed) {
  const std::string empty = write("");
  EXPECT_EQ(read_error(empty), empty + ": no records: an input without records is not a trace");
  ReaderOptions allowed;
  allowed.allow_empty = true;
  EXPECT_TRUE(read_all(empty, allowed).records.empty());
  EXPECT_EQ(with_stdin_from("", [] { read_all("-"); }),
            "<stdin>: no records: an input without records is not a trace (did the command before the pipe fail?)");
  const std::string container = (dir_ / "none.din.zst").string();
  write_trace(container, {}, WriterOptions{});
  EXPECT_EQ(read_error(container), container + ": no records: an input without records is not a trace");
  EXPECT_TRUE(read_all(container, allowed).records.empty());
  EXPECT_EQ(with_stdin_from(nodetrace::testing::read_file(container), [] { read_all("-"); }),
            "<stdin>: no records: an input without records is not a trace (did the command before the pipe fail?)");
}

TEST_F(TextParsing, DinRejectionsNameTheRecordAndTheFault) {
  EXPECT_EQ(error_of("0\n"), (dir_ / "t.din").string() + ": record 1: short line");
  EXPECT_NE(error_of("0 100\n\n0 100\n").find("record 2: short line"), std::string::npos);
  EXPECT_NE(error_of("0 100\n0 100\n\n").find("record 3: short line"), std::string::npos);
  EXPECT_NE(error_of("0 10g\n").find("record 1: non hex digit (code 0x67) in address"), std::string::npos);
  EXPECT_NE(error_of("0 -100\n").find("record 1: non hex digit (code 0x2d) in address"), std::string::npos);
  EXPECT_NE(error_of("0 100\r\n").find("record 1: non hex digit (code 0xd) in address"), std::string::npos);
  EXPECT_NE(error_of("0 1\n0 1\n0 1\n0 1\n7 100\n").find("record 5: label 7 is not a Dinero IV access type (0-5)"),
            std::string::npos);
  EXPECT_NE(error_of("6 100\n").find("label 6 is not"), std::string::npos);
  EXPECT_NE(error_of("0 1\na 100\n").find("record 2: label a is not"), std::string::npos);
  EXPECT_NE(error_of("10 100\n").find("label 10 is not"), std::string::npos);
  EXPECT_NE(error_of("0 10000000000000000\n").find("record 1: address wider than 64 bits"), std::string::npos);
  EXPECT_NE(error_of("0g 100\n").find("non hex digit (code 0x67) in label"), std::string::npos);
  EXPECT_NE(error_of("0 0x\n").find("no hex digits in address"), std::string::npos);
}

TEST_F(TextParsing, ExtendedDinAcceptsAndRejects) {
  const auto result = read_all(write("r 100 4\nw 0x200 8 07 more\ni 300 10\nm 0 1\nc 8 4\nv 10 4\n"));
  ASSERT_EQ(result.records.size(), 6u);
  EXPECT_EQ(result.form, RecordForm::ExtendedDin);
  EXPECT_EQ(result.records[1], (Record{0x200, 8, AccessType::Write, TraversalUnit{}, kTagNone}));
  EXPECT_EQ(result.records[2].size, 16u);
  EXPECT_EQ(result.records[5].type, AccessType::Invalidate);
  EXPECT_NE(error_of("r 100 4\nx 100 4\n").find("record 2: unknown access type 'x'"), std::string::npos);
  EXPECT_NE(error_of("r 100\n").find("record 1: missing size"), std::string::npos);
  EXPECT_NE(error_of("r 100 \n").find("record 1: missing size"), std::string::npos);
  EXPECT_NE(error_of("r 100 4z\n").find("non hex digit (code 0x7a) in size"), std::string::npos);
  EXPECT_NE(error_of("r 100 0\n").find("size 0"), std::string::npos);
  EXPECT_NE(error_of("r 100 123456789\n").find("size wider than 32 bits"), std::string::npos);
  EXPECT_NE(error_of("r\n").find("short line"), std::string::npos);
}

TEST_F(TextParsing, TagsAreIgnoredUnlessTheyAreLevels) {
  const std::string text = "0 100 07\n0 200 p\n1 300 t\n0 400 123\n";
  for (const auto& record : read_all(write(text)).records) EXPECT_EQ(record.tag, kTagNone);
  ReaderOptions levels;
  levels.tags_are_levels = true;
  const auto tagged = read_all(write(text), levels);
  ASSERT_EQ(tagged.records.size(), 4u);
  EXPECT_TRUE(tagged.tags_are_levels);
  EXPECT_EQ(tagged.records[0].tag, 7);
  EXPECT_EQ(tagged.records[1].tag, kTagPrimitiveList);
  EXPECT_EQ(tagged.records[2].tag, kTagTriangle);
  EXPECT_EQ(tagged.records[3].tag, 123);
}

TEST_F(TextParsing, LevelTagErrors) {
  ReaderOptions levels;
  levels.tags_are_levels = true;
  EXPECT_NE(error_of("0 100 07\n0 100\n", levels).find("record 2: missing tag"), std::string::npos);
  EXPECT_NE(error_of("0 100 q\n", levels).find("record 1: tag 'q' is neither a decimal node level nor p or t"),
            std::string::npos);
  EXPECT_NE(error_of("0 100 7x\n", levels).find("tag '7x'"), std::string::npos);
  EXPECT_NE(error_of("0 100 99999\n", levels).find("above the largest node level"), std::string::npos);
  EXPECT_NE(error_of("r 100 4\n", levels).find("record 1: missing tag"), std::string::npos);
  EXPECT_EQ(read_all(write("r 100 8 05\n"), levels).records.at(0), (Record{0x100, 8, AccessType::Read, TraversalUnit{}, 5}));
}

TEST_F(TextParsing, FastPathAndGeneralParserAgree) {
  // Fixed-width lines (fast path) interleaved with lines only the general
  // parser takes must give the same records as all-general input.
  std::string fixed, loose;
  for (int i = 0; i < 5000; ++i) {
    const unsigned address = 0x1000 + i * 8;
    const int level = i % 40;
    if (i % 97 == 5) {
      fixed += line("0   %x\t%d\n", address, level);
    } else {
      fixed += line("0 %08x %02d\n", address, level);
    }
    loose += line("  0 0x%x %d\n", address, level);
  }
  ReaderOptions levels;
  levels.tags_are_levels = true;
  const auto a = read_all(write(fixed, "fixed.din"), levels);
  const auto b = read_all(write(loose, "loose.din"), levels);
  ASSERT_EQ(a.records.size(), 5000u);
  EXPECT_EQ(a.records, b.records);
  EXPECT_EQ(a.records[40].tag, 0);
  EXPECT_EQ(a.records[41].tag, 1);
}

TEST_F(TextParsing, EveryByteOfTheCommonLineIsCheckedAsTheGeneralParserChecksIt) {
  // `0 00001a38 07` with one byte changed to each value near a boundary of
  // what is accepted (digits, letters, blanks, controls, high bytes), after a line of
  // the common layout (the fast path reads it) and after one of another
  // layout (only the general parser reads it): the same records or the same
  // error, with the same record number.
  const std::string common = "0 00001a38 07\n";
  const std::string tail = common + common;
  ReaderOptions levels;
  levels.tags_are_levels = true;
  levels.threads = 1;
  const auto outcome = [&](const std::string& text, const char* name) {
    try {
      auto result = read_all(write(text, name), levels);
      result.records.erase(result.records.begin());
      return fmt::format("{} records, second {:x} {} {}", result.records.size(),
                         result.records.empty() ? 0 : result.records[0].address,
                         result.records.empty() ? 0 : static_cast<int>(result.records[0].type),
                         result.records.empty() ? 0 : result.records[0].tag);
    } catch (const base::FormatError& error) {
      const std::string message = error.what();
      return message.substr(message.find(": ") + 2);  // without the file name
    }
  };
  std::vector<int> values = {0, '\t', '\n', '\r', ' ', '/', ':', '@', 'G', '`', 'g', 'x', 'X', 0x7f, 0x80, 0xb0, 0xc1, 0xe6, 0xff};
  for (int c = '0'; c <= '9'; ++c) values.push_back(c);
  for (int c = 'a'; c <= 'f'; ++c) values.push_back(c), values.push_back(c - 'a' + 'A');
  int differing = 0;
  for (std::size_t position = 0; position + 1 < common.size(); ++position) {
    for (const int value : values) {
      std::string changed = common;
      changed[position] = static_cast<char>(value);
      const std::string fast = outcome(common + changed + tail, "fast.din");
      const std::string general = outcome("0 0000001a38 07\n" + changed + tail, "general.din");
      if (fast != general && ++differing <= 5) {
        ADD_FAILURE() << "byte " << position << " = " << value << ": fast path gives \"" << fast
                      << "\", the general parser \"" << general << "\"";
      }
    }
  }
  EXPECT_EQ(differing, 0);
}

TEST_F(TextParsing, ErrorsAfterTheFastPathCountRecordsExactly) {
  std::string text;
  for (int i = 0; i < 300000; ++i) text += "0 00001a38 07\n";  // several parse chunks
  text += "0 00001a3g 07\n";
  EXPECT_NE(error_of(text).find("record 300001: non hex digit (code 0x67) in address"), std::string::npos);
}

TEST_F(TextParsing, BinaryRecordsMustBeNamed) {
  std::string bytes;
  const unsigned char record[8] = {0x38, 0x1a, 0, 0, 8, 0, 1, 0};
  bytes.append(reinterpret_cast<const char*>(record), 8);
  bytes.append(reinterpret_cast<const char*>(record), 8);
  ReaderOptions binary;
  binary.form = RecordForm::Binary;
  const auto result = read_all(write(bytes, "t.bin"), binary);
  ASSERT_EQ(result.records.size(), 2u);
  EXPECT_EQ(result.records[1], (Record{0x1a38, 8, AccessType::Write, TraversalUnit{}, kTagNone}));
  EXPECT_NE(read_error(write(bytes + "abc", "t.bin"), binary).find("record 3: truncated record: 3 bytes of 8"),
            std::string::npos);
  std::string bad = bytes;
  bad[14] = 9;
  EXPECT_NE(read_error(write(bad, "t.bin"), binary).find("record 2: type 9 is not a Dinero IV access type"),
            std::string::npos);
  binary.tags_are_levels = true;
  EXPECT_THROW(TraceReader::open(write(bytes, "t.bin"), binary), base::UsageError);
}

TEST_F(TextParsing, MissingFileIsAnIoError) {
  EXPECT_THROW(TraceReader::open((dir_ / "absent.din").string()), base::IoError);
}

}  // namespace
}  // namespace nodetrace::formats
