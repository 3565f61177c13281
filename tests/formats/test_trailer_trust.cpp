// What a trailer states is what the file holds (issue 52 items 1, 4, 5):
// `tracetool verify` checks every total against the records, info refuses
// an index that does not fit the file, counts beyond 64 bits are refused,
// and two containers joined by `cat` are named as such, file or pipe.
#include <gtest/gtest.h>

#define XXH_INLINE_ALL
#include <xxhash.h>

#include <nlohmann/json.hpp>

#include <functional>
#include <string>

#include "container/container.hpp"
#include "formats_test_util.hpp"
#include "test_support.hpp"

namespace nodetrace::formats {
namespace {

using detail::append_le32;
using detail::append_le64;
using detail::load_le32;
using nodetrace::testing::program;
using nodetrace::testing::read_file;
using nodetrace::testing::run_command;
using nodetrace::testing::shell_quoted;
using nodetrace::testing::TempDir;
using nodetrace::testing::write_file;

// The file's bytes with its trailer JSON text replaced by `edit` of it, the
// footer's hash and length made to match (so only the totals lie).
std::string with_trailer_text(const std::string& file, const std::function<std::string(std::string)>& edit) {
  const std::size_t json_size = load_le32(file.data() + file.size() - detail::kFooterSize + 8);
  const std::size_t start = file.size() - detail::kFooterSize - json_size - detail::kSkippableHeaderSize;
  const std::string text = edit(file.substr(start + detail::kSkippableHeaderSize, json_size));
  std::string payload = text;
  append_le64(payload, XXH64(text.data(), text.size(), 0));
  append_le32(payload, static_cast<std::uint32_t>(text.size()));
  append_le32(payload, detail::kContainerVersion);
  append_le32(payload, detail::kFooterMagic);
  return file.substr(0, start) + detail::skippable_frame(detail::kTrailerMagic, payload);
}

// The same, editing the trailer as JSON.
std::string with_trailer(const std::string& file, const std::function<void(nlohmann::json&)>& edit) {
  return with_trailer_text(file, [&](const std::string& text) {
    nlohmann::json json = nlohmann::json::parse(text);
    edit(json);
    return json.dump();
  });
}

class TrailerTrust : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!std::filesystem::exists(program("tracetool"))) GTEST_SKIP() << "tracetool is not built";
    // 101 records of levels 0-29 and one p, two animation frames, 4 data frames.
    std::vector<Record> records = testing_util::sample_records(101);
    records.back().tag = kTagPrimitiveList;
    WriterOptions options;
    options.records_per_data_frame = 30;
    AnimationFrameMarker first, second;
    first.frame = 0;
    second.frame = 1;
    testing_util::write_trace(path("t.din.zst"), records, options, {{"producer", {{"tool", "unit"}}}},
                              {{0, first}, {60, second}});
    original_ = read_file(dir_ / "t.din.zst");
    // A second, different trace (one animation frame, 2 data frames).
    records.resize(40);
    testing_util::write_trace(path("u.din.zst"), records, options, {{"producer", {{"tool", "other"}}}}, {});
  }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  nodetrace::testing::CommandResult tracetool(const std::string& args, const std::string& input = {}) const {
    return run_command(shell_quoted(program("tracetool")) + " " + args, input);
  }
  TempDir dir_;
  std::string original_;
};

TEST_F(TrailerTrust, VerifyChecksEveryTotalTheTrailerStates) {
  const auto clean = tracetool("verify " + shell_quoted(path("t.din.zst")));
  ASSERT_EQ(clean.exit_code, 0) << clean.err;
  EXPECT_EQ(clean.out, "OK: 101 records, 2 animation frames, 4 data frames\n");
  // Each total given a false value, the footer's hash recomputed: verify
  // names the total; info, which reads only the trailer, prints it.
  // (The reader itself checks records, with its own words.)
  const auto records = tracetool("verify -", with_trailer(original_, [](nlohmann::json& t) { t["totals"]["records"] = 102; }));
  EXPECT_EQ(records.exit_code, 1);
  EXPECT_NE(records.err.find("the trailer's totals say 102 records but the data frames hold 101"), std::string::npos)
      << records.err;
  const std::vector<std::pair<std::string, std::function<void(nlohmann::json&)>>> lies = {
      {"animation_frames 3", [](nlohmann::json& t) { t["totals"]["animation_frames"] = 3; }},
      {"records_per_tag.3 1000", [](nlohmann::json& t) { t["totals"]["records_per_tag"]["3"] = 1000; }},
      {"records_per_tag.p 0", [](nlohmann::json& t) { t["totals"]["records_per_tag"].erase("p"); }},
      {"records_per_tag.30 1", [](nlohmann::json& t) { t["totals"]["records_per_tag"]["30"] = 1; }},
      {"records_per_type.write 1", [](nlohmann::json& t) { t["totals"]["records_per_type"]["write"] = 1; }},
      {"data_frames 5", [](nlohmann::json& t) { t["totals"]["data_frames"] = 5; }},
      {"record_bytes 1", [](nlohmann::json& t) { t["totals"]["record_bytes"] = 1; }},
      {"sample_windows 2", [](nlohmann::json& t) { t["totals"]["sample_windows"] = 2; }},
  };
  for (const auto& [lie, edit] : lies) {
    write_file(dir_ / "lie.din.zst", with_trailer(original_, edit));
    const auto verified = tracetool("verify " + shell_quoted(path("lie.din.zst")));
    EXPECT_EQ(verified.exit_code, 1) << lie << ": " << verified.out;
    EXPECT_NE(verified.err.find("the trailer's totals say " + lie + ", but"), std::string::npos)
        << lie << ": " << verified.err;
    // The same bytes from a pipe, where the trailer comes last.
    const auto piped = tracetool("verify -", with_trailer(original_, edit));
    EXPECT_EQ(piped.exit_code, 1) << lie;
    EXPECT_NE(piped.err.find("say " + lie), std::string::npos) << lie << ": " << piped.err;
  }
}

TEST_F(TrailerTrust, ACountBeyond64BitsIsRefusedNotShownAsZero) {
  for (const std::string key : {"records", "animation_frames", "record_bytes"}) {
    write_file(dir_ / "big.din.zst", with_trailer_text(original_, [&](std::string text) {
                 const std::size_t at = text.find("\"" + key + "\":");
                 const std::size_t value = at + key.size() + 3;
                 return text.replace(value, text.find_first_of(",}", value) - value, "18446744073709551621");
               }));
    for (const char* command : {"info", "info --format json", "verify", "cat"}) {
      const auto result = tracetool(std::string(command) + " " + shell_quoted(path("big.din.zst")));
      EXPECT_EQ(result.exit_code, 1) << key << ", " << command << ": " << result.out;
      EXPECT_NE(result.err.find("trailer: totals." + key + " is 1.8446744073709552e+19, not a count (an integer "
                                "from 0 to 2^64 - 1)"),
                std::string::npos)
          << key << ", " << command << ": " << result.err;
    }
  }
}

TEST_F(TrailerTrust, InfoRefusesAnIndexThatDoesNotFitTheFile) {
  // One index entry moved by a byte: every reader, info too, refuses at once.
  write_file(dir_ / "moved.din.zst", with_trailer(original_, [](nlohmann::json& t) {
               t["index"][2][0] = t["index"][2][0].get<std::uint64_t>() + 1;
             }));
  for (const char* command : {"info", "verify", "cat"}) {
    const auto result = tracetool(std::string(command) + " " + shell_quoted(path("moved.din.zst")));
    EXPECT_EQ(result.exit_code, 1) << command;
    EXPECT_NE(result.err.find("damaged: the trailer's index does not fit the file: data frame 3 at byte"),
              std::string::npos)
        << command << ": " << result.err;
  }
  // Another trace's trailer (the content and record hashes too) on this one's frames.
  const std::string other = read_file(dir_ / "u.din.zst");
  const std::size_t other_json = load_le32(other.data() + other.size() - detail::kFooterSize + 8);
  const std::size_t other_start = other.size() - detail::kFooterSize - other_json - detail::kSkippableHeaderSize;
  const std::size_t json = load_le32(original_.data() + original_.size() - detail::kFooterSize + 8);
  write_file(dir_ / "swapped.din.zst",
             original_.substr(0, original_.size() - detail::kFooterSize - json - detail::kSkippableHeaderSize) +
                 other.substr(other_start));
  const auto info = tracetool("info " + shell_quoted(path("swapped.din.zst")));
  EXPECT_EQ(info.exit_code, 1) << info.out;
  EXPECT_NE(info.err.find("the trailer's index does not fit the file"), std::string::npos) << info.err;
}

TEST_F(TrailerTrust, JoinedTracesAreNamedFromAFileAndFromAPipe) {
  const std::string other = read_file(dir_ / "u.din.zst");
  for (const auto& [name, bytes, second] :
       {std::tuple{"t+u", original_ + other, original_.size()}, std::tuple{"u+t", other + original_, other.size()}}) {
    write_file(dir_ / "joined.din.zst", bytes);
    const std::string expected = "two traces joined: a second trace's header begins at byte " + std::to_string(second);
    for (const char* command : {"info", "verify", "cat"}) {
      const auto from_file = tracetool(std::string(command) + " " + shell_quoted(path("joined.din.zst")));
      EXPECT_EQ(from_file.exit_code, 1) << name << " " << command;
      EXPECT_NE(from_file.err.find(expected), std::string::npos) << name << " " << command << ": " << from_file.err;
      const auto from_pipe = tracetool(std::string(command) + " -", bytes);
      EXPECT_EQ(from_pipe.exit_code, 1) << name << " " << command << " -";
      EXPECT_NE(from_pipe.err.find(expected), std::string::npos) << name << " " << command << " -: " << from_pipe.err;
    }
  }
}

// Issue 52 item 12: one data frame is "1 data frame" in every message.
TEST_F(TrailerTrust, OneDataFrameIsSingularInMessages) {
  WriterOptions options;
  options.records_per_data_frame = 30;
  testing_util::write_trace(path("one.din.zst"), testing_util::sample_records(20), options);
  const std::string one = read_file(dir_ / "one.din.zst");
  const std::size_t json = load_le32(one.data() + one.size() - detail::kFooterSize + 8);
  const std::string cut = one.substr(0, one.size() - detail::kFooterSize - json - detail::kSkippableHeaderSize);
  const auto truncated = tracetool("verify -", cut);
  EXPECT_EQ(truncated.exit_code, 1);
  EXPECT_NE(truncated.err.find("truncated: the file ends after 1 data frame without the trailer"), std::string::npos)
      << truncated.err;
  write_file(dir_ / "lie.din.zst", with_trailer(one, [](nlohmann::json& t) { t["totals"]["data_frames"] = 2; }));
  const auto lie = tracetool("verify " + shell_quoted(path("lie.din.zst")));
  EXPECT_NE(lie.err.find("the trailer's totals say data_frames 2, but the file has 1 data frame\n"),
            std::string::npos)
      << lie.err;
}

}  // namespace
}  // namespace nodetrace::formats
