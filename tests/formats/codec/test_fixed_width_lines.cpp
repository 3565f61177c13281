// The fixed-width text the writers produce, checked line by line against a
// plain fmt rendering of FORMAT.md 1.1 / 1.2: the table-driven common line
// (32-bit address, level below 100) and the general path must agree, also
// for records mixed in one batch; format_record, one record at a time, gives
// the same lines and the unpadded untagged lines Dinero IV is fed.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <random>
#include <string>
#include <vector>

#include "nodetrace/base/error.hpp"
#include "nodetrace/formats/record/record_format.hpp"
#include "nodetrace/formats/write/trace_writer.hpp"
#include "test_support.hpp"

namespace nodetrace::formats {
namespace {

using nodetrace::testing::read_file;
using nodetrace::testing::TempDir;

std::string expected_line(const Record& record, RecordForm form, unsigned digits) {
  constexpr char kLetters[] = "rwimcv";
  const auto type = static_cast<unsigned>(record.type);
  std::string line = form == RecordForm::Din ? fmt::format("{} ", type) : fmt::format("{} ", kLetters[type]);
  line += fmt::format("{:0{}x}", record.address, digits);
  if (form == RecordForm::ExtendedDin) line += fmt::format(" {:x}", record.size);
  if (record.tag == kTagPrimitiveList) line += " p";
  if (record.tag == kTagTriangle) line += " t";
  if (is_level(record.tag)) line += fmt::format(" {:02}", record.tag);
  return line + "\n";
}

std::vector<Record> mixed_records() {
  std::mt19937_64 random(7);
  std::vector<Record> records;
  for (int i = 0; i < 20000; ++i) {
    Record record;
    const auto pick = random();
    record.address = pick % 10 == 0 ? random() >> (pick % 40) : random() & 0xFFFFFFFFu;  // some above 32 bits
    record.size = 1 + static_cast<std::uint32_t>(random() % (pick % 7 == 0 ? 0x12345 : 16));
    record.type = static_cast<AccessType>(random() % kAccessTypeCount);
    const auto tag_kind = random() % 20;
    record.tag = tag_kind == 0   ? kTagPrimitiveList
                 : tag_kind == 1 ? kTagTriangle
                 : tag_kind == 2 ? kTagNone
                 : tag_kind == 3 ? static_cast<Tag>(100 + random() % 65000)
                                 : static_cast<Tag>(random() % 100);
    records.push_back(record);
  }
  records.push_back({0xFFFFFFFFu, 15, AccessType::Invalidate, TraversalUnit{}, 99});
  records.push_back({0x100000000ull, 16, AccessType::Read, TraversalUnit{}, 0});
  records.push_back({0, 1, AccessType::Read, TraversalUnit{}, 100});
  return records;
}

TEST(FixedWidthLines, DinAndExtendedDinMatchTheSpecificationForEveryKindOfRecord) {
  TempDir dir;
  const auto records = mixed_records();
  for (const RecordForm form : {RecordForm::Din, RecordForm::ExtendedDin}) {
    for (const unsigned digits : {8u, 16u}) {
      WriterOptions options;
      options.form = form;
      options.kind = OutputKind::Plain;
      options.address_digits = digits;
      options.records_per_data_frame = 7777;  // several frames, in pieces
      const auto path = dir / fmt::format("t{}{}.txt", static_cast<int>(form), digits);
      auto writer = TraceWriter::create(path.string(), nullptr, options);
      writer->write(std::span<const Record>(records).first(5000));
      writer->write(std::span<const Record>(records).subspan(5000));
      writer->finish();
      std::string expected;
      for (const Record& record : records) expected += expected_line(record, form, digits);
      const std::string text = read_file(path);
      ASSERT_EQ(text.size(), expected.size()) << form_name(form) << " " << digits;
      EXPECT_TRUE(text == expected) << form_name(form) << " " << digits;
    }
  }
}

TEST(FixedWidthLines, FormatRecordWritesTheWritersLinesAndDineroIVsLines) {
  char line[kMaxFormattedRecord];
  for (const Record& record : mixed_records()) {
    for (const RecordForm form : {RecordForm::Din, RecordForm::ExtendedDin}) {
      for (const unsigned digits : {8u, 16u}) {
        const std::size_t length = format_record(record, form, TextLayout{digits, true}, line);
        ASSERT_EQ(std::string(line, length), expected_line(record, form, digits));
      }
      Record untagged = record;
      untagged.tag = kTagNone;
      const std::size_t length = format_record(record, form, kDineroTextLayout, line);
      ASSERT_EQ(std::string(line, length), expected_line(untagged, form, 1));
    }
  }
}

TEST(FixedWidthLines, FormatRecordWritesTheWritersBinaryRecords) {
  TempDir dir;
  std::vector<Record> records;
  for (const Record& record : mixed_records()) {
    if (record.address <= 0xFFFFFFFFu && record.size <= 0xFFFFu) records.push_back(record);
  }
  WriterOptions options;
  options.form = RecordForm::Binary;
  options.kind = OutputKind::Plain;
  auto writer = TraceWriter::create((dir / "t.bin").string(), nullptr, options);
  writer->write(records);
  writer->finish();
  std::string formatted;
  char bytes[kMaxFormattedRecord];
  for (const Record& record : records) formatted.append(bytes, format_record(record, RecordForm::Binary, {}, bytes));
  EXPECT_TRUE(formatted == read_file(dir / "t.bin"));
  EXPECT_THROW(format_record({0x100000000ull, 4, AccessType::Read, TraversalUnit{}, kTagNone}, RecordForm::Binary, {}, bytes),
               base::FormatError);
  EXPECT_THROW(format_record({0x1000, 0x10000, AccessType::Read, TraversalUnit{}, kTagNone}, RecordForm::Binary, {}, bytes),
               base::FormatError);
}

TEST(FixedWidthLines, ABadRecordInABatchKeepsTheOnesBeforeItAndIsNamed) {
  TempDir dir;
  WriterOptions options;
  options.kind = OutputKind::Container;
  auto writer = TraceWriter::create((dir / "t.din.zst").string(), nullptr, options);
  std::vector<Record> records(10, Record{0x1000, 4, AccessType::Read, TraversalUnit{}, 3});
  records[6].tag = kTagNone;
  try {
    writer->write(records);
    FAIL() << "an untagged record in a node-level trace was accepted";
  } catch (const base::FormatError& error) {
    EXPECT_NE(std::string(error.what()).find("record 7: untagged"), std::string::npos) << error.what();
  }
}

}  // namespace
}  // namespace nodetrace::formats
