// The traversal unit field (DESIGN.md "Trace records": `0 00001a38 07 3`):
// written fixed-width after the tag when a trace has several units, read
// back where the header says "units", ignored as Dinero IV ignores it
// otherwise, and filtered by `tracetool cat --unit`.
#include <gtest/gtest.h>

#include <string>

#include <fmt/format.h>

#include "codec/record_codec.hpp"
#include "formats_test_util.hpp"
#include "test_support.hpp"

namespace nodetrace::formats {
namespace {

using nodetrace::testing::program;
using nodetrace::testing::read_file;
using nodetrace::testing::run_command;
using nodetrace::testing::TempDir;
using nodetrace::testing::write_file;
using testing_util::read_all;

std::vector<Record> records_of_units(std::size_t count, unsigned units) {
  std::vector<Record> records = testing_util::sample_records(count, 7);
  for (std::size_t i = 0; i < records.size(); ++i) records[i].unit = traversal_unit(static_cast<unsigned>((i * 7 + i / 3) % units));
  return records;
}

std::vector<Record> parse(const std::string& text, const detail::ParseSettings& settings, std::string* error_text = nullptr) {
  std::vector<Record> out;
  detail::RecordError error;
  std::uint64_t ignored = 0;
  const bool ok = detail::parse_records(text, settings, out, error, ignored);
  if (error_text) *error_text = ok ? "" : error.message;
  EXPECT_TRUE(ok || error_text) << error.message;
  return out;
}

TEST(UnitField, WrittenFixedWidthAfterTheTagWithTheDigitsOfTheLargestUnit) {
  char line[kMaxFormattedRecord];
  const Record record{0x1a38, 8, AccessType::Read, traversal_unit(3), 7};
  const auto text = [&](RecordForm form, unsigned digits) {
    return std::string(line, format_record(record, form, TextLayout{8, true, digits}, line));
  };
  EXPECT_EQ(text(RecordForm::Din, 0), "0 00001a38 07\n");
  EXPECT_EQ(text(RecordForm::Din, 1), "0 00001a38 07 3\n");
  EXPECT_EQ(text(RecordForm::Din, 2), "0 00001a38 07 03\n");
  EXPECT_EQ(text(RecordForm::ExtendedDin, 3), "r 00001a38 8 07 003\n");
  EXPECT_EQ(unit_digits_for(1), 0u);
  EXPECT_EQ(unit_digits_for(4), 1u);
  EXPECT_EQ(unit_digits_for(10), 1u);
  EXPECT_EQ(unit_digits_for(11), 2u);
  EXPECT_EQ(unit_digits_for(256), 3u);
}

// The same records as the writer's fixed-width lines (fast path) and as
// lines of any width (general parser): both read back exactly.
TEST(UnitField, FastPathAndGeneralParserReadTheSameUnits) {
  for (const RecordForm form : {RecordForm::Din, RecordForm::ExtendedDin}) {
    for (const unsigned units : {4u, 16u, 200u}) {
      std::vector<Record> records = records_of_units(500, units);
      if (form == RecordForm::Din) {
        for (Record& record : records) record.size = 4;
      }
      detail::ByteBuffer fixed;
      RecordSummary summary;
      detail::format_records(records, form, 8, unit_digits_for(units), 0, fixed, summary);
      // Unpadded fields, as another tool might write them: `0 1a38 7 3`.
      std::string loose;
      for (const Record& record : records) {
        const auto type = static_cast<unsigned>(record.type);
        loose += form == RecordForm::Din
                     ? fmt::format("{} {:x} {} {}\n", type, record.address, record.tag, unit_index(record.unit))
                     : fmt::format("{} {:x} {:x} {} {}\n", "rwimcv"[type], record.address, record.size, record.tag,
                                   unit_index(record.unit));
      }
      ASSERT_NE(loose.substr(0, 20), std::string(fixed.data(), 20));
      const detail::ParseSettings settings{form, true, units};
      EXPECT_EQ(parse(std::string(fixed.data(), fixed.size()), settings), records) << units;
      EXPECT_EQ(parse(loose, settings), records) << units;
    }
  }
}

TEST(UnitField, IgnoredAsDineroIvIgnoresItWhereTheTraceDoesNotSaySo) {
  const std::string text = "0 00001a38 07 3\n0 00001a40 08 2\n";
  for (const unsigned units : {1u, 4u}) {
    // Tags not read as levels: everything after the address is ignored.
    const auto untagged = parse(text, {RecordForm::Din, false, units});
    ASSERT_EQ(untagged.size(), 2u);
    EXPECT_EQ(untagged[0].tag, kTagNone);
    EXPECT_EQ(untagged[0].unit, TraversalUnit{});
  }
  // Levels, but no "units" in the header: the level is read, the unit is not.
  const auto levels = parse(text, {RecordForm::Din, true, 1});
  ASSERT_EQ(levels.size(), 2u);
  EXPECT_EQ(levels[1].tag, 8);
  EXPECT_EQ(levels[1].unit, TraversalUnit{});
  // With it, both.
  EXPECT_EQ(parse(text, {RecordForm::Din, true, 4})[1].unit, traversal_unit(2));
}

TEST(UnitField, MissingOrForeignUnitsAreErrorsWhereTheHeaderSaysUnits) {
  std::string error;
  parse("0 00001a38 07 3\n0 00001a40 08\n", {RecordForm::Din, true, 4}, &error);
  EXPECT_NE(error.find("missing unit"), std::string::npos) << error;
  parse("0 00001a38 07 4\n", {RecordForm::Din, true, 4}, &error);
  EXPECT_NE(error.find("unit '4' is not a traversal unit of this trace (0 to 3)"), std::string::npos) << error;
  parse("r 1a38 8 07 x\n", {RecordForm::ExtendedDin, true, 4}, &error);
  EXPECT_NE(error.find("unit 'x'"), std::string::npos) << error;
}

class UnitContainer : public ::testing::Test {
 protected:
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  TempDir dir_;
};

TEST_F(UnitContainer, WrittenAndReadBackWithTheHeaderSayingHowManyUnits) {
  for (const char* name : {"t.din.zst", "t.xdin.zst"}) {
    std::vector<Record> records = records_of_units(3000, 12);
    WriterOptions options;
    options.form = std::string(name) == "t.din.zst" ? RecordForm::Din : RecordForm::ExtendedDin;
    if (options.form == RecordForm::Din) {
      for (Record& record : records) record.size = 4;
    }
    options.units = 12;
    options.records_per_data_frame = 1000;
    testing_util::write_trace(path(name), records, options);
    auto reader = TraceReader::open(path(name));
    EXPECT_EQ(reader->units(), 12u);
    EXPECT_EQ(reader->header().json.at("units"), 12);
    EXPECT_EQ(read_all(path(name)).records, records) << name;
  }
}

TEST_F(UnitContainer, OneUnitWritesNeitherTheFieldNorTheHeaderKey) {
  const std::vector<Record> records = testing_util::sample_records(100);
  WriterOptions options;
  testing_util::write_trace(path("one.din.zst"), records, options);
  testing_util::write_trace(path("plain.din"), records, options);
  EXPECT_FALSE(TraceReader::open(path("one.din.zst"))->header().json.contains("units"));
  EXPECT_EQ(read_file(dir_ / "plain.din").find('\n'), 13u);  // `0 AAAAAAAA LL`: no unit
}

TEST_F(UnitContainer, WriterRefusesUnitsItCannotWrite) {
  WriterOptions options;
  options.units = 2;
  auto writer = TraceWriter::create(path("w.din.zst"), {}, options);
  EXPECT_THROW(writer->write(Record{0x10, 4, AccessType::Read, traversal_unit(2), 1}), base::FormatError);
  options.form = RecordForm::Binary;
  EXPECT_THROW(TraceWriter::create(path("w.bin"), {}, options), base::UsageError);
  options.form = RecordForm::Din;
  options.units = kMaxUnits + 1;
  EXPECT_THROW(TraceWriter::create(path("x.din.zst"), {}, options), base::UsageError);
}

TEST_F(UnitContainer, TracetoolCatExtractsOneUnitAndConvertKeepsThemAll) {
  if (!std::filesystem::exists(program("tracetool"))) GTEST_SKIP() << "tracetool is not built";
  std::vector<Record> records = records_of_units(2000, 3);
  for (Record& record : records) record.size = 4;
  WriterOptions options;
  options.units = 3;
  testing_util::write_trace(path("u.din.zst"), records, options);
  const std::string tool = nodetrace::testing::shell_quoted(program("tracetool"));
  const std::string trace = nodetrace::testing::shell_quoted(path("u.din.zst"));
  for (unsigned unit = 0; unit < 3; ++unit) {
    const auto result = run_command(tool + " cat --unit " + std::to_string(unit) + " " + trace);
    ASSERT_EQ(result.exit_code, 0) << result.err;
    std::string expected;
    char line[kMaxFormattedRecord];
    for (const Record& record : records) {
      if (record.unit == traversal_unit(unit)) expected.append(line, format_record(record, RecordForm::Din, kTraceTextLayout, line));
    }
    EXPECT_EQ(result.out, expected) << unit;
  }
  // Without --unit the field stays: the text zstdcat shows.
  const auto all = run_command(tool + " cat " + trace);
  EXPECT_EQ(all.out.substr(0, all.out.find('\n') + 1).size(), 16u) << all.out.substr(0, 40);
  const auto bad = run_command(tool + " cat --unit 3 " + trace);
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("units 0 to 2"), std::string::npos) << bad.err;
  const auto convert = run_command(tool + " convert " + trace + " " + nodetrace::testing::shell_quoted(path("c.xdin.zst")) + " --to xdin");
  ASSERT_EQ(convert.exit_code, 0) << convert.err;
  const auto converted = read_all(path("c.xdin.zst")).records;
  ASSERT_EQ(converted.size(), records.size());
  for (std::size_t i = 0; i < records.size(); ++i) ASSERT_EQ(converted[i].unit, records[i].unit) << i;
  // A trace of one unit is unit 0's whole; it has no unit 1.
  testing_util::write_trace(path("one.din.zst"), testing_util::sample_records(10), WriterOptions{});
  const std::string one = nodetrace::testing::shell_quoted(path("one.din.zst"));
  EXPECT_EQ(run_command(tool + " cat --unit 0 " + one).out, run_command(tool + " cat " + one).out);
  const auto no_unit = run_command(tool + " cat --unit 1 " + one);
  EXPECT_EQ(no_unit.exit_code, 2);
  EXPECT_NE(no_unit.err.find("carry no unit"), std::string::npos) << no_unit.err;
}

TEST(UnitHeader, UnitsThatAreNoCountAreAnError) {
  TraceHeader header;
  header.json = {{"units", 0}};
  EXPECT_THROW(header.units(), base::FormatError);
  header.json = {{"units", "4"}};
  EXPECT_THROW(header.units(), base::FormatError);
  header.json = {{"units", 4}};
  EXPECT_EQ(header.units(), 4u);
}

}  // namespace
}  // namespace nodetrace::formats
