// tracetool end to end: exit codes, messages, filtering, conversion.
#include <gtest/gtest.h>

#include <cstdio>

#include "formats_test_util.hpp"
#include "test_support.hpp"

namespace nodetrace::formats {
namespace {

using nodetrace::testing::program;
using nodetrace::testing::read_file;
using nodetrace::testing::run_command;
using nodetrace::testing::TempDir;
using nodetrace::testing::write_file;

class Tracetool : public ::testing::Test {
 protected:
  static std::string quoted(const std::string& text) {
    std::string result(1, '\'');
    result += text;
    result += '\'';
    return result;
  }
  std::string tool() const { return quoted(program("tracetool").string()); }
  std::string path(const std::string& name) const { return quoted((dir_ / name).string()); }
  nodetrace::testing::CommandResult run(const std::string& args, const std::string& input = {}) const {
    return run_command(tool() + " " + args, input);
  }
  void SetUp() override {
    if (!std::filesystem::exists(program("tracetool"))) GTEST_SKIP() << "tracetool is not built";
    std::vector<Record> records;
    for (int i = 0; i < 100; ++i) {
      records.push_back({0x1000u + 8u * i, 8, AccessType::Read, TraversalUnit{}, static_cast<Tag>(i % 12)});
    }
    records.push_back({0x9000, 8, AccessType::Read, TraversalUnit{}, kTagPrimitiveList});
    WriterOptions options;
    options.records_per_data_frame = 30;
    AnimationFrameMarker first;
    first.frame = 0;
    AnimationFrameMarker second;
    second.frame = 1;
    testing_util::write_trace((dir_ / "t.din.zst").string(), records, options, {{"producer", {{"tool", "unit"}}}},
                              {{0, first}, {60, second}});
  }
  TempDir dir_;
};

TEST_F(Tracetool, HelpAndUsageErrors) {
  for (const char* command : {"--help", "info --help", "cat --help", "verify --help", "convert --help"}) {
    const auto result = run(command);
    EXPECT_EQ(result.exit_code, 0) << command;
    EXPECT_NE(result.out.find("Usage"), std::string::npos) << command;
  }
  EXPECT_EQ(run("").exit_code, 2);
  EXPECT_EQ(run("frobnicate").exit_code, 2);
  EXPECT_EQ(run("cat --to elf " + path("t.din.zst")).exit_code, 2);
  const auto bad_tags = run("cat --tags 3-1 " + path("t.din.zst"));
  EXPECT_EQ(bad_tags.exit_code, 2);
  EXPECT_NE(bad_tags.err.find("range '3-1' is empty"), std::string::npos) << bad_tags.err;
}

TEST_F(Tracetool, VerifyReportsRecordsAndFrames) {
  const auto result = run("verify " + path("t.din.zst"));
  EXPECT_EQ(result.exit_code, 0) << result.err;
  EXPECT_EQ(result.out, "OK: 101 records, 2 animation frames, 4 data frames\n");
  const auto piped = run("verify -", read_file(dir_ / "t.din.zst"));
  EXPECT_EQ(piped.out, "OK: 101 records, 2 animation frames, 4 data frames\n");
}

TEST_F(Tracetool, VerifyFailsOnDamage) {
  std::string bytes = read_file(dir_ / "t.din.zst");
  std::string flipped = bytes;
  flipped[bytes.size() / 2] ^= 0x01;
  write_file(dir_ / "flipped.din.zst", flipped);
  auto result = run("verify " + path("flipped.din.zst"));
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_NE(result.err.find("flipped.din.zst: "), std::string::npos) << result.err;
  write_file(dir_ / "cut.din.zst", bytes.substr(0, bytes.size() - 10));
  result = run("verify " + path("cut.din.zst"));
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_NE(result.err.find("truncated"), std::string::npos) << result.err;
  result = run("verify -", bytes.substr(0, bytes.size() - 10));
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_NE(result.err.find("<stdin>"), std::string::npos) << result.err;
  write_file(dir_ / "bad.din", "0 100\n0 10g\n");
  result = run("verify " + path("bad.din"));
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_NE(result.err.find("bad.din: record 2: non hex digit (code 0x67) in address"), std::string::npos)
      << result.err;
  result = run("verify " + path("absent.din"));
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_NE(result.err.find("absent.din: cannot open"), std::string::npos) << result.err;
}

TEST_F(Tracetool, CatFiltersByTag) {
  auto result = run("cat --tags 0-1,10-,p " + path("t.din.zst"));
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const std::size_t lines = static_cast<std::size_t>(std::count(result.out.begin(), result.out.end(), '\n'));
  // Levels 0,1,10,11 of i % 12 over 100 records: 9+9+8+8, plus the p record.
  EXPECT_EQ(lines, 35u);
  EXPECT_EQ(result.out.substr(0, 28), "0 00001000 00\n0 00001008 01\n");
  EXPECT_NE(result.out.find("0 00009000 p\n"), std::string::npos);
  result = run("cat --to xdin --tags 5 " + path("t.din.zst"));
  EXPECT_EQ(result.out.substr(0, 16), "r 00001028 4 05\n");
}

TEST_F(Tracetool, CatByLevelOfAnUntaggedTraceSaysWhy) {
  write_file(dir_ / "plain.din", "0 100 07\n0 200 03\n");
  auto result = run("cat --tags 0-3 " + path("plain.din"));
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.err.find("--tags-are-levels"), std::string::npos) << result.err;
  result = run("cat --tags-are-levels --tags 0-3 " + path("plain.din"));
  EXPECT_EQ(result.exit_code, 0);
  EXPECT_EQ(result.out, "0 00000200 03\n");
  result = run("cat -", "0 100\n");
  EXPECT_EQ(result.out, "0 00000100\n");
}

TEST_F(Tracetool, ConvertCarriesHeaderMarkersAndTags) {
  auto result = run("convert --threads 1 --frame-records 7 --zstd-level 5 " + path("t.din.zst") + " " +
                    path("c.xdin.zst") + " --to xdin");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  auto reader = TraceReader::open((dir_ / "c.xdin.zst").string());
  EXPECT_EQ(reader->form(), RecordForm::ExtendedDin);
  EXPECT_TRUE(reader->tags_are_levels());
  EXPECT_EQ(reader->header().json.at("producer").at("tool"), "unit");
  EXPECT_EQ(reader->trailer()->index.size(), 15u);  // 60 = 9 frames of 7 (last 4), 41 = 6 (last 6)
  EXPECT_EQ(reader->trailer()->totals.at("animation_frames"), 2);
  // Plain text in, level container out, and back to plain text.
  write_file(dir_ / "in.din", "0 100 07\n2 200 p\n");
  result = run("convert --tags-are-levels " + path("in.din") + " " + path("in.din.zst"));
  ASSERT_EQ(result.exit_code, 0) << result.err;
  result = run("info --format json " + path("in.din.zst"));
  const auto info = nlohmann::json::parse(result.out);
  EXPECT_EQ(info.at("records"), 2);
  EXPECT_EQ(info.at("tags"), "node-level");
  EXPECT_EQ(info.at("records_per_tag").at("7"), 1);
  EXPECT_EQ(info.at("records_per_tag").at("p"), 1);
  EXPECT_EQ(info.at("records_per_type").at("instruction_fetch"), 1);
  result = run("convert " + path("in.din.zst") + " " + path("out.din"));
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_EQ(read_file(dir_ / "out.din"), "0 00000100 07\n2 00000200 p\n");
  result = run("convert " + path("in.din.zst") + " -");
  EXPECT_EQ(result.out.substr(0, 4), std::string("\x50\x2a\x4d\x18", 4));
  result = run("convert " + path("missing.din") + " " + path("x.din.zst"));
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_FALSE(std::filesystem::exists(dir_ / "x.din.zst"));
}

TEST_F(Tracetool, ConvertArchiveKeepsTheRecordsAndRejectsConflictingOptions) {
  auto result = run("convert --archive " + path("t.din.zst") + " " + path("a.din.zst"));
  ASSERT_EQ(result.exit_code, 0) << result.err;
  auto archive = TraceReader::open((dir_ / "a.din.zst").string());
  auto original = TraceReader::open((dir_ / "t.din.zst").string());
  EXPECT_EQ(archive->header().json.at("compression"), nlohmann::json({{"level", 17}, {"window_log", 26}}));
  EXPECT_EQ(archive->header().json.at("producer").at("tool"), "unit");
  // The same totals; only the data frames are fewer (4194304 records each).
  nlohmann::json totals = original->trailer()->totals;
  totals["data_frames"] = 2;  // one per animation frame
  EXPECT_EQ(archive->trailer()->totals, totals);
  EXPECT_EQ(archive->trailer()->record_hash, original->trailer()->record_hash);
  EXPECT_EQ(testing_util::read_all((dir_ / "a.din.zst").string()).records,
            testing_util::read_all((dir_ / "t.din.zst").string()).records);
  EXPECT_EQ(run("verify " + path("a.din.zst")).exit_code, 0);
  for (const std::string bad : {"--archive --zstd-level 5", "--archive --frame-records 7", "--archive=bogus"}) {
    result = run("convert " + bad + " " + path("t.din.zst") + " " + path("b.din.zst"));
    EXPECT_EQ(result.exit_code, 2) << bad;
    EXPECT_NE(result.err.find("--archive"), std::string::npos) << result.err;
    EXPECT_FALSE(std::filesystem::exists(dir_ / "b.din.zst"));
  }
}

TEST_F(Tracetool, InfoOnPlainTracesReads) {
  write_file(dir_ / "p.xdin", "r 100 8\nw 200 4\n");
  const auto result = run("info --format json " + path("p.xdin"));
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const auto info = nlohmann::json::parse(result.out);
  EXPECT_EQ(info.at("records"), 2);
  EXPECT_EQ(info.at("kind"), "plain");
  EXPECT_EQ(info.at("records_form"), "xdin");
  EXPECT_EQ(info.at("decompressed_bytes"), 16);
  EXPECT_EQ(info.at("bytes_per_record"), 8.0);
  const auto table = run("info " + path("t.din.zst"));
  EXPECT_NE(table.out.find("records              101"), std::string::npos) << table.out;
}

TEST_F(Tracetool, DroppedTrailingFieldsAreCountedOnStandardError) {
  // Fixed-width tagged lines (the fast path) and free-form ones.
  std::string text;
  char line[32];
  for (int i = 0; i < 50; ++i) {
    std::snprintf(line, sizeof line, "0 %08x %02d\n", 0x1000 + 8 * i, i % 10);
    text += line;
  }
  text += "0 2000\n1 2004  \n0 2008 comment here\n";
  write_file(dir_ / "tagged.din", text);
  // 50 tagged lines and the comment; trailing blanks are no field.
  const std::string warning = "51 records had fields after the address (e.g. a level tag) that were dropped; "
                              "pass --tags-are-levels to keep a tag field of node levels";
  for (const std::string& command : {"convert " + path("tagged.din") + " " + path("out.din.zst"),
                                     "cat " + path("tagged.din")}) {
    const auto result = run(command);
    EXPECT_EQ(result.exit_code, 0) << command << "\n" << result.err;
    EXPECT_EQ(result.err, "tracetool: warning: " + (dir_ / "tagged.din").string() + ": " + warning + "\n")
        << command;
  }
  // With --tags-are-levels the tags are kept: nothing is dropped.
  write_file(dir_ / "levels.din", text.substr(0, text.find("0 2000")));
  const auto kept = run("convert --tags-are-levels " + path("levels.din") + " " + path("levels.din.zst"));
  EXPECT_EQ(kept.exit_code, 0) << kept.err;
  EXPECT_EQ(kept.err, "");
  const auto untagged = run("cat " + path("t.din.zst"));
  EXPECT_EQ(untagged.err, "");
}

}  // namespace
}  // namespace nodetrace::formats
