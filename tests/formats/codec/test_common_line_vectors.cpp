// The commonest line, `0 00001a38 07`, read by each vector unit the processor
// has (AVX-512, AVX2, scalar: fixed_width_lines.hpp): with any byte of any
// line of a group changed, each takes every line before it, gives for every
// line it takes the general parser's record, and stops at a line the general
// parser rejects; and written by each unit as the scalar writer writes it.
// Internal: the codec is tested directly (formats/src).
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <optional>
#include <span>
#include <random>
#include <string>
#include <vector>

#include "codec/fixed_width_lines.hpp"

namespace nodetrace::formats {
namespace {

using detail::VectorUnits;

std::vector<VectorUnits> units_here() {
  std::vector<VectorUnits> units = {VectorUnits::Scalar};
  if (detail::best_vector_units() >= VectorUnits::Avx2) units.push_back(VectorUnits::Avx2);
  if (detail::best_vector_units() >= VectorUnits::Avx512) units.push_back(VectorUnits::Avx512);
  return units;
}

// The general parser's reading of one line (a leading blank keeps the fast
// paths off it): the record, or nullopt when it rejects the line.
std::optional<Record> general_record(const std::string& line, bool tags) {
  detail::ParseSettings settings;
  settings.tags_are_levels = tags;
  std::vector<Record> records;
  detail::RecordError error;
  std::uint64_t ignored = 0;
  if (!detail::parse_records(" " + line + "\n", settings, records, error, ignored) || records.size() != 1) {
    return std::nullopt;
  }
  return records[0];
}

std::vector<std::string> common_lines(std::size_t count) {
  std::mt19937_64 random(5);
  std::vector<std::string> lines;
  for (std::size_t i = 0; i < count; ++i) {
    const auto address = static_cast<std::uint32_t>(random());
    const auto type = random() % 6;
    const auto level = random() % 100;
    lines.push_back(random() % 2 ? fmt::format("{} {:08x} {:02}", type, address, level)
                                 : fmt::format("{} {:08X} {:02}", type, address, level));
  }
  return lines;
}

// Parses `lines` with `units` and checks the three properties against the
// general parser; `changed` is the index of the changed line.
void expect_general_records(const std::vector<std::string>& lines, std::size_t changed, bool tags,
                            VectorUnits units) {
  std::string text;
  for (const std::string& line : lines) text += line + "\n";
  std::vector<Record> records;
  const std::size_t taken = detail::din8_tagged_lines(text.data(), text.data() + text.size(), tags, records, units);
  ASSERT_EQ(taken % 14, 0u);
  ASSERT_EQ(records.size(), taken / 14);
  const auto trace = [&] { return fmt::format("units {}, line {}: \"{}\"", static_cast<int>(units), changed,
                                              lines[changed]); };
  EXPECT_GE(records.size(), changed) << trace();
  for (std::size_t i = 0; i < records.size(); ++i) {
    const auto expected = general_record(lines[i], tags);
    ASSERT_TRUE(expected.has_value()) << "took a line the general parser rejects, " << trace();
    EXPECT_EQ(records[i], *expected) << "line " << i << ", " << trace();
  }
}

TEST(CommonLineVectors, EveryUnitTakesTheCommonLinesAsTheGeneralParserReadsThem) {
  const auto lines = common_lines(301);
  for (const bool tags : {false, true}) {
    for (const VectorUnits units : units_here()) expect_general_records(lines, lines.size() - 2, tags, units);
  }
}

TEST(CommonLineVectors, EveryByteOfEveryLineOfAGroupChangedGivesTheGeneralParsersRecordsOrStops) {
  std::vector<int> values = {0, '\t', '\n', '\r', ' ', '/', ':', '@', 'G', '`', 'g', 'x', 'X', 0x7f, 0x80, 0xb0, 0xc1,
                             0xe6, 0xff};
  for (int c = '0'; c <= '9'; ++c) values.push_back(c);
  for (int c = 'a'; c <= 'f'; ++c) values.push_back(c), values.push_back(c - 'a' + 'A');
  const auto base = common_lines(24);
  // Lines 8-15: each lane of a four-line group and of a two-line pair, at
  // both alignments of a group's start.
  for (std::size_t changed = 8; changed < 16; ++changed) {
    for (std::size_t position = 0; position < 13; ++position) {
      for (const int value : values) {
        auto lines = base;
        lines[changed][position] = static_cast<char>(value);
        for (const bool tags : {false, true}) {
          for (const VectorUnits units : units_here()) {
            expect_general_records(lines, changed, tags, units);
            if (::testing::Test::HasFailure()) return;
          }
        }
      }
    }
  }
}

// Records of every kind the writer meets, runs of common ones between them:
// a wide address, a level of 100 or more, p, t and no tag each fall in every
// lane of a four-record group.
std::vector<Record> records_to_write() {
  std::mt19937_64 random(17);
  std::vector<Record> records;
  for (int i = 0; i < 4000; ++i) {
    Record record;
    record.address = static_cast<std::uint32_t>(random()) >> (random() % 32);
    record.type = static_cast<AccessType>(random() % 6);
    record.tag = static_cast<Tag>(random() % 100);
    switch (random() % 16) {
      case 0: record.address |= std::uint64_t{1} << (32 + random() % 32); break;
      case 1: record.tag = static_cast<Tag>(100 + random() % (kMaxLevel - 99)); break;
      case 2: record.tag = kTagPrimitiveList; break;
      case 3: record.tag = kTagTriangle; break;
      case 4: record.tag = kTagNone; break;
      default: break;
    }
    records.push_back(record);
  }
  return records;
}

TEST(CommonLineVectors, EveryUnitWritesTheLinesAndCountsTheScalarWriterDoes) {
  const std::vector<Record> records = records_to_write();
  for (std::size_t count : {records.size(), records.size() - 1, records.size() - 3, std::size_t{5}, std::size_t{3}}) {
    const std::span<const Record> run(records.data(), count);
    detail::ByteBuffer expected;
    RecordSummary expected_summary;
    detail::format_text_records<false>(run, 8, 0, expected, expected_summary, VectorUnits::Scalar);
    for (const VectorUnits units : units_here()) {
      detail::ByteBuffer text;
      text.append("x", 1);  // after bytes already there, as a writer appends
      RecordSummary summary;
      detail::format_text_records<false>(run, 8, 0, text, summary, units);
      EXPECT_EQ(text.view().substr(1), expected.view()) << "units " << static_cast<int>(units) << ", " << count;
      EXPECT_EQ(summary.records(), count);
      EXPECT_EQ(summary.records_per_tag(), expected_summary.records_per_tag());
      EXPECT_EQ(summary.records_per_type(), expected_summary.records_per_type());
    }
  }
}

}  // namespace
}  // namespace nodetrace::formats
