// The trace container: round trips, byte-for-byte zstd compatibility,
// determinism across thread counts, markers through a pipe, seeking, and
// damage / truncation detection.
#include <gtest/gtest.h>
#include <unistd.h>
#include <xxhash.h>

#include <cstdio>
#include <thread>

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
using testing_util::read_error;
using testing_util::sample_records;
using testing_util::write_trace;

AnimationFrameMarker marker(std::uint64_t frame) {
  AnimationFrameMarker result;
  result.frame = frame;
  result.time = 0.5 * static_cast<double>(frame);
  result.nodes_per_level = {1, 2, 4};
  result.nodes = 7;
  result.leaves = 4;
  result.depth = 3;
  result.extra["note"] = "kept";
  return result;
}

// What reading back gives for records written in `form`.
std::vector<Record> as_read_back(std::vector<Record> records, RecordForm form, bool levels) {
  for (auto& record : records) {
    if (form == RecordForm::Din) record.size = 4;
    if (form == RecordForm::Binary || !levels) record.tag = kTagNone;
  }
  return records;
}

WriterOptions options_for(RecordForm form, std::uint64_t per_animation_frame = 1000, unsigned threads = 2) {
  WriterOptions options;
  options.form = form;
  options.records_per_data_frame = per_animation_frame;
  options.threads = threads;
  return options;
}

class Container : public ::testing::Test {
 protected:
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  TempDir dir_;
};

TEST_F(Container, ADataFrameLargerThanItsZstdWindowReadsBackExactly) {
  // 1.5 M records (21 MB of text) in one data frame: zstd's window is
  // smaller than the frame, so the reader's ring wraps and records cut by
  // the wrap are joined; the records and the record hash come out right.
  const auto records = sample_records(1500000, 9);
  const std::string file = path("one-frame.din.zst");
  write_trace(file, records, options_for(RecordForm::Din, 1500000));
  const std::string bytes = read_file(file);
  const auto frame = bytes.find("\x28\xb5\x2f\xfd");
  ASSERT_NE(frame, std::string::npos);
  const auto descriptor = static_cast<unsigned char>(bytes[frame + 4]);
  ASSERT_EQ(descriptor & 0x20, 0) << "a single-segment frame has its whole content as its window";
  const auto window = static_cast<unsigned char>(bytes[frame + 5]);
  // Window Descriptor: at most twice 2^(10 + exponent).
  EXPECT_LT(1ull << (11 + (window >> 3)), 1500000ull * 14) << "the window must be smaller than the frame";
  EXPECT_EQ(read_all(file).records, as_read_back(records, RecordForm::Din, true));
}

TEST_F(Container, DataFramesOfManyRecordsAreDeliveredInSmallerBatchesWithMarkersInPlace) {
  // Data frames of 200000 records (a reader hands a frame over in several
  // batches): the records, the markers' places and first_record are as
  // written, from a file, through a pipe, and after a seek into a frame.
  const auto records = sample_records(700000, 5);
  const std::vector<std::pair<std::uint64_t, AnimationFrameMarker>> markers = {{0, marker(0)}, {450000, marker(1)}};
  const std::string file = path("big.din.zst");
  write_trace(file, records, options_for(RecordForm::Din, 200000), {}, markers);
  const auto expected = as_read_back(records, RecordForm::Din, true);
  ReaderOptions skip_record_hash;
  skip_record_hash.check_record_hash = false;
  for (const ReaderOptions& options : {ReaderOptions{}, skip_record_hash}) {
    auto reader = TraceReader::open(file, options);
    RecordBatch batch;
    std::vector<Record> read;
    std::vector<std::uint64_t> marker_places;
    std::size_t batches = 0;
    while (reader->next(batch)) {
      ASSERT_EQ(batch.first_record, read.size());
      if (batch.marker) marker_places.push_back(batch.first_record);
      read.insert(read.end(), batch.records.begin(), batch.records.end());
      ++batches;
    }
    EXPECT_EQ(read, expected);
    EXPECT_EQ(marker_places, (std::vector<std::uint64_t>{0, 450000}));
    EXPECT_GT(batches, 5u);  // more batches than data frames
  }
  const std::string bytes = read_file(file);
  const std::string error = testing_util::with_stdin_from(bytes, [&] {
    const auto piped = read_all("-");
    EXPECT_EQ(piped.records, expected);
    ASSERT_EQ(piped.markers.size(), 2u);
    EXPECT_EQ(piped.markers[1].first, 450000u);
  });
  EXPECT_EQ(error, "");
  auto reader = TraceReader::open(file);
  reader->seek_to_record(300001);  // in the second data frame, which starts at record 200000
  RecordBatch batch;
  ASSERT_TRUE(reader->next(batch));
  EXPECT_EQ(batch.first_record, 200000u);
  std::vector<Record> rest(batch.records.begin(), batch.records.end());
  while (reader->next(batch)) rest.insert(rest.end(), batch.records.begin(), batch.records.end());
  EXPECT_EQ(rest, std::vector<Record>(expected.begin() + 200000, expected.end()));
}

TEST_F(Container, TheRecordHashIsCheckedWhateverTheDecodingThreads) {
  // Fifteen data frames, decoded by one to three workers that hash their
  // text in frame order: the true record hash passes, and a trailer that
  // names another one (footer made to match) is a record hash mismatch.
  const auto records = sample_records(300000, 3);
  const std::string file = path("hashed.din.zst");
  write_trace(file, records, options_for(RecordForm::Din, 20000));
  std::string bytes = read_file(file);
  const std::size_t key = bytes.rfind("\"record_hash\":\"");
  ASSERT_NE(key, std::string::npos);
  char& digit = bytes[key + 15];
  digit = digit == '0' ? '1' : '0';
  const std::size_t footer = bytes.size() - 20;
  const std::uint32_t json_size = static_cast<unsigned char>(bytes[footer + 8]) |
                                  static_cast<unsigned char>(bytes[footer + 9]) << 8 |
                                  static_cast<unsigned char>(bytes[footer + 10]) << 16 |
                                  static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[footer + 11])) << 24;
  const std::uint64_t json_hash = XXH64(bytes.data() + footer - json_size, json_size, 0);
  for (int i = 0; i < 8; ++i) bytes[footer + i] = static_cast<char>(json_hash >> (8 * i));
  const std::string changed = path("other-hash.din.zst");
  write_file(changed, bytes);
  const auto expected = as_read_back(records, RecordForm::Din, true);
  for (const unsigned threads : {1u, 2u, 3u}) {
    ReaderOptions options;
    options.threads = threads;
    EXPECT_EQ(read_all(file, options).records, expected) << threads << " threads";
    EXPECT_NE(read_error(changed, options).find("record hash mismatch"), std::string::npos) << threads << " threads";
    options.check_record_hash = false;
    EXPECT_EQ(read_all(changed, options).records, expected) << threads << " threads";
  }
}

TEST_F(Container, BatchesSayWhetherEveryRecordIsADemandFetchAndALevel) {
  // 100000 reads of levels, a copy-back at record 30000 and a leaf-list
  // record at 70000, as a container and as plain text: each batch's kinds
  // are what its records are, and both answers occur.
  auto records = sample_records(100000, 4);
  records[30000].type = AccessType::CopyBack;
  records[70000].tag = kTagPrimitiveList;
  const std::string container = path("flags.din.zst");
  const std::string plain = path("flags.din");
  write_trace(container, records, options_for(RecordForm::Din, 50000));
  write_trace(plain, records, options_for(RecordForm::Din, 50000));
  ReaderOptions levels;
  levels.tags_are_levels = true;
  for (const std::string& file : {container, plain}) {
    auto reader = TraceReader::open(file, levels);
    RecordBatch batch;
    std::size_t read = 0, flagged = 0, unflagged = 0;
    while (reader->next(batch)) {
      const RecordKinds kinds = record_kinds(batch.records.data(), batch.records.size());
      EXPECT_EQ(batch.kinds.demand_fetches, kinds.demand_fetches) << file << ", batch at record " << batch.first_record;
      EXPECT_EQ(batch.kinds.levels, kinds.levels) << file << ", batch at record " << batch.first_record;
      (batch.kinds.demand_fetches && batch.kinds.levels ? flagged : unflagged) += 1;
      read += batch.records.size();
    }
    EXPECT_EQ(read, records.size()) << file;
    EXPECT_GT(flagged, 0u) << file;
    EXPECT_GE(unflagged, 2u) << file;
  }
  // Read untagged, the plain text's records are demand fetches but no levels.
  auto reader = TraceReader::open(plain);
  RecordBatch batch;
  std::size_t demand_batches = 0;
  while (reader->next(batch)) {
    EXPECT_FALSE(batch.kinds.levels);
    EXPECT_EQ(batch.kinds.demand_fetches, record_kinds(batch.records.data(), batch.records.size()).demand_fetches);
    demand_batches += batch.kinds.demand_fetches;
  }
  EXPECT_GT(demand_batches, 0u);
}

TEST_F(Container, RoundTripsEveryFormWithMarkers) {
  const auto records = sample_records(5500);
  const std::vector<std::pair<std::uint64_t, AnimationFrameMarker>> markers = {{0, marker(0)}, {2000, marker(1)},
                                                                      {2000, marker(2)}, {5500, marker(3)}};
  for (const RecordForm form : {RecordForm::Din, RecordForm::ExtendedDin, RecordForm::Binary}) {
    const std::string file = path(std::string("t.") + std::string(form_name(form)) + ".zst");
    write_trace(file, records, options_for(form), {{"scene", {{"name", "unit"}}}}, markers);
    const auto result = read_all(file);
    EXPECT_EQ(result.form, form);
    EXPECT_EQ(result.tags_are_levels, form != RecordForm::Binary);
    EXPECT_EQ(result.records, as_read_back(records, form, true)) << form_name(form);
    ASSERT_EQ(result.markers.size(), 4u);
    for (std::size_t i = 0; i < markers.size(); ++i) {
      EXPECT_EQ(result.markers[i].first, markers[i].first);
      EXPECT_EQ(result.markers[i].second.frame, markers[i].second.frame);
      EXPECT_EQ(result.markers[i].second.nodes_per_level, markers[i].second.nodes_per_level);
      EXPECT_EQ(result.markers[i].second.extra.at("note"), "kept");
    }
    auto reader = TraceReader::open(file);
    EXPECT_EQ(reader->header().json.at("scene").at("name"), "unit");
    ASSERT_TRUE(reader->trailer());
    const auto& totals = reader->trailer()->totals;
    EXPECT_EQ(totals.at("records"), 5500u);
    EXPECT_EQ(totals.at("animation_frames"), 4u);
    EXPECT_EQ(totals.at("records_per_type").at("read"), 5500u);
    // 2000, then 0 for the empty frame 1... frames: [0,1000),[1000,2000),[2000..5500) in 4 frames.
    EXPECT_EQ(reader->trailer()->index.size(), 6u);
    EXPECT_EQ(reader->trailer()->index[2].animation_frame, 2u);
    EXPECT_EQ(reader->trailer()->index[5].record_count, 500u);
  }
}

TEST_F(Container, PlainOutputRoundTrips) {
  const auto records = sample_records(3000);
  for (const RecordForm form : {RecordForm::Din, RecordForm::ExtendedDin, RecordForm::Binary}) {
    const std::string file = path("plain.out");
    write_trace(file, records, options_for(form));
    ReaderOptions options;
    options.form = form == RecordForm::Binary ? std::optional(RecordForm::Binary) : std::nullopt;
    options.tags_are_levels = form != RecordForm::Binary;
    const auto result = read_all(file, options);
    EXPECT_EQ(result.form, form);
    EXPECT_EQ(result.records, as_read_back(records, form, true));
  }
  std::vector<Record> untagged = {{0x1a38, 4, AccessType::Write, TraversalUnit{}, kTagNone}};
  write_trace(path("u.din"), untagged, options_for(RecordForm::Din));
  EXPECT_EQ(read_file(path("u.din")), "1 00001a38\n");
  WriterOptions wide = options_for(RecordForm::ExtendedDin);
  wide.address_digits = 16;
  write_trace(path("w.xdin"), {{0x1a38, 8, AccessType::Read, TraversalUnit{}, 7}}, wide);
  EXPECT_EQ(read_file(path("w.xdin")), "r 0000000000001a38 8 07\n");
}

TEST_F(Container, ZstdProgramDecompressesToTheRecordText) {
  const auto records = sample_records(20000);
  write_trace(path("t.din.zst"), records, options_for(RecordForm::Din, 3000), {}, {{0, marker(0)}, {7000, marker(1)}});
  write_trace(path("t.din"), records, options_for(RecordForm::Din));
  const auto result = run_command("zstd -dc '" + path("t.din.zst") + "'");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_EQ(result.out, read_file(path("t.din")));
  EXPECT_EQ(result.out.substr(0, 14), "0 " + result.out.substr(2, 8) + " " + result.out.substr(11, 2) + "\n");
}

TEST_F(Container, BytesDoNotDependOnThreadCount) {
  const auto records = sample_records(30000);
  write_trace(path("one.din.zst"), records, options_for(RecordForm::Din, 2500, 1), {}, {{0, marker(0)}});
  write_trace(path("two.din.zst"), records, options_for(RecordForm::Din, 2500, 2), {}, {{0, marker(0)}});
  write_trace(path("four.din.zst"), records, options_for(RecordForm::Din, 2500, 4), {}, {{0, marker(0)}});
  const std::string one = read_file(path("one.din.zst"));
  EXPECT_EQ(one, read_file(path("two.din.zst")));
  EXPECT_EQ(one, read_file(path("four.din.zst")));
  ReaderOptions single;
  single.threads = 1;
  EXPECT_EQ(read_all(path("one.din.zst"), single).records, read_all(path("one.din.zst")).records);
}

TEST_F(Container, MarkersArriveInOrderThroughAPipe) {
  const auto records = sample_records(9000);
  std::vector<std::pair<std::uint64_t, AnimationFrameMarker>> markers;
  for (std::uint64_t frame = 0; frame < 6; ++frame) markers.emplace_back(frame * 1500, marker(frame));
  markers.emplace_back(9000, marker(6));  // an animation frame with no records
  write_trace(path("t.din.zst"), records, options_for(RecordForm::Din, 700), {}, markers);
  const std::string bytes = read_file(path("t.din.zst"));

  testing_util::ReadResult result;
  const std::string error = testing_util::with_stdin_from(bytes, [&] {
    auto reader = TraceReader::open("-");
    EXPECT_EQ(reader->source_name(), "<stdin>");
    EXPECT_FALSE(reader->trailer());
    RecordBatch batch;
    while (reader->next(batch)) {
      if (batch.marker) result.markers.emplace_back(result.records.size(), *batch.marker);
      result.records.insert(result.records.end(), batch.records.begin(), batch.records.end());
    }
    EXPECT_TRUE(reader->trailer());  // available once the stream has ended
    EXPECT_THROW(reader->seek_to_record(0), base::UsageError);
  });
  ASSERT_EQ(error, "");
  EXPECT_EQ(result.records, as_read_back(records, RecordForm::Din, true));
  ASSERT_EQ(result.markers.size(), markers.size());
  for (std::size_t i = 0; i < markers.size(); ++i) {
    EXPECT_EQ(result.markers[i].first, markers[i].first);
    EXPECT_EQ(result.markers[i].second.frame, i);
  }
}

TEST_F(Container, SeeksByTheIndex) {
  const auto records = sample_records(10000);
  write_trace(path("t.xdin.zst"), records, options_for(RecordForm::ExtendedDin, 1000));
  auto reader = TraceReader::open(path("t.xdin.zst"));
  reader->seek_to_record(4321);
  RecordBatch batch;
  ASSERT_TRUE(reader->next(batch));
  EXPECT_EQ(batch.first_record, 4000u);
  ASSERT_EQ(batch.records.size(), 1000u);
  EXPECT_EQ(batch.records[321], records[4321]);
  std::uint64_t rest = batch.records.size();
  while (reader->next(batch)) rest += batch.records.size();
  EXPECT_EQ(rest, 6000u);
  EXPECT_THROW(reader->seek_to_record(10000), base::UsageError);
}

TEST_F(Container, ReadsPlainZstdFromOtherToolsAndSkipsUnknownSkippableFrames) {
  write_file(path("t.din"), "2 130\n0 ff2f80 x\n1 ff2f84\n");
  ASSERT_EQ(run_command("zstd -q -c '" + path("t.din") + "' > '" + path("t.din.zst") + "'").exit_code, 0);
  auto result = read_all(path("t.din.zst"));
  ASSERT_EQ(result.records.size(), 3u);
  EXPECT_EQ(result.records[1], (Record{0xff2f80, 4, AccessType::Read, TraversalUnit{}, kTagNone}));
  // Someone else's skippable frame in front (magic 0x184D2A53, 3 bytes).
  const std::string skippable("\x53\x2a\x4d\x18\x03\x00\x00\x00xyz", 11);
  write_file(path("s.din.zst"), skippable + read_file(path("t.din.zst")));
  EXPECT_EQ(read_all(path("s.din.zst")).records, result.records);
  // Two concatenated zstd frames (as `cat a.zst b.zst` makes).
  write_file(path("c.din.zst"), read_file(path("t.din.zst")) + read_file(path("t.din.zst")));
  EXPECT_EQ(read_all(path("c.din.zst")).records.size(), 6u);
  write_file(path("x.xdin"), "r 100 4\n");
  ASSERT_EQ(run_command("zstd -q -c '" + path("x.xdin") + "' > '" + path("x.xdin.zst") + "'").exit_code, 0);
  EXPECT_EQ(read_all(path("x.xdin.zst")).form, RecordForm::ExtendedDin);
  // A damaged plain zstd stream.
  std::string damaged = read_file(path("t.din.zst"));
  damaged.resize(damaged.size() - 3);
  write_file(path("d.din.zst"), damaged);
  EXPECT_NE(read_error(path("d.din.zst")), "");
}

TEST_F(Container, WriterUsesATemporaryFileAndRemovesItWhenAbandoned) {
  {
    auto writer = TraceWriter::create(path("t.din.zst"), {}, options_for(RecordForm::Din));
    writer->write(sample_records(10));
    EXPECT_FALSE(std::filesystem::exists(path("t.din.zst")));
  }
  EXPECT_TRUE(std::filesystem::is_empty(dir_.path()));
  write_trace(path("t.din.zst"), sample_records(10), options_for(RecordForm::Din));
  std::size_t files = 0;
  for ([[maybe_unused]] const auto& entry : std::filesystem::directory_iterator(dir_.path())) ++files;
  EXPECT_EQ(files, 1u);
}

TEST_F(Container, WriterRejectsWhatItCannotWrite) {
  auto writer = TraceWriter::create(path("t.din.zst"), {}, options_for(RecordForm::Din));
  EXPECT_THROW(writer->write(Record{0x100, 4, AccessType::Read, TraversalUnit{}, kTagNone}), base::FormatError);
  auto binary = TraceWriter::create(path("t.bin"), {}, options_for(RecordForm::Binary));
  EXPECT_THROW(binary->write(Record{0x100000000ull, 4, AccessType::Read, TraversalUnit{}, kTagNone}), base::FormatError);
  WriterOptions bad = options_for(RecordForm::Din);
  bad.address_digits = 12;
  EXPECT_THROW(TraceWriter::create(path("u.din.zst"), {}, bad), base::UsageError);
  // Untagged records in a container that does not claim levels are fine.
  WriterOptions untagged = options_for(RecordForm::Din);
  untagged.tags_are_levels = false;
  write_trace(path("u.din.zst"), {{0x100, 4, AccessType::Read, TraversalUnit{}, kTagNone}}, untagged);
  const auto result = read_all(path("u.din.zst"));
  EXPECT_FALSE(result.tags_are_levels);
  EXPECT_EQ(result.records.size(), 1u);
}

// The window a data frame's zstd frame header announces (RFC 8878 3.1.1.1):
// the Window_Descriptor's size, or for a single-segment frame its content size.
std::uint64_t announced_window(const std::string& file, std::uint64_t offset) {
  const auto byte = [&](std::uint64_t at) { return static_cast<unsigned char>(file.at(offset + at)); };
  const unsigned descriptor = byte(4);
  if ((descriptor & 0x20) == 0) {
    const unsigned window = byte(5);
    const std::uint64_t base = std::uint64_t{1} << (10 + (window >> 3));
    return base + base / 8 * (window & 7);
  }
  const unsigned dictionary_bytes[] = {0, 1, 2, 4};
  const unsigned content_bytes[] = {1, 2, 4, 8};
  const std::uint64_t at = 5 + dictionary_bytes[descriptor & 3];
  const unsigned size_bytes = content_bytes[descriptor >> 6];
  std::uint64_t size = 0;
  for (unsigned i = 0; i < size_bytes; ++i) size |= std::uint64_t{byte(at + i)} << (8 * i);
  return size_bytes == 2 ? size + 256 : size;
}

TEST_F(Container, ArchiveSettingKeepsEveryRecordAndRecordsItsWindow) {
  const auto records = sample_records(60000);
  const std::vector<std::pair<std::uint64_t, AnimationFrameMarker>> markers = {{0, marker(0)}, {25000, marker(1)}};
  write_trace(path("default.din.zst"), records, options_for(RecordForm::Din, 1u << 20), {}, markers);
  WriterOptions archive = options_for(RecordForm::Din);
  use_archive_setting(archive);
  EXPECT_EQ(archive.zstd_level, 17);
  EXPECT_EQ(archive.window_log, 26u);
  EXPECT_EQ(archive.records_per_data_frame, 4194304u);
  write_trace(path("archive.din.zst"), records, archive, {}, markers);

  const auto wrote = read_all(path("default.din.zst"));
  const auto kept = read_all(path("archive.din.zst"));
  EXPECT_EQ(kept.records, wrote.records);
  ASSERT_EQ(kept.markers.size(), 2u);
  EXPECT_EQ(kept.markers[1].first, 25000u);
  EXPECT_EQ(kept.markers[1].second.to_json(), marker(1).to_json());
  auto archive_reader = TraceReader::open(path("archive.din.zst"));
  auto default_reader = TraceReader::open(path("default.din.zst"));
  EXPECT_EQ(archive_reader->trailer()->totals, default_reader->trailer()->totals);
  EXPECT_EQ(archive_reader->trailer()->record_hash, default_reader->trailer()->record_hash);
  EXPECT_EQ(archive_reader->header().json.at("compression"),
            nlohmann::json({{"level", 17}, {"window_log", 26}}));
  EXPECT_FALSE(default_reader->header().json.contains("compression"));
  // Every data frame's own header announces at most the recorded window.
  const std::string bytes = read_file(path("archive.din.zst"));
  for (const auto& entry : archive_reader->trailer()->index) {
    EXPECT_LE(announced_window(bytes, entry.offset), std::uint64_t{1} << 26);
  }
  EXPECT_LT(bytes.size(), read_file(path("default.din.zst")).size());
  // zstd reads it as it reads the default container: the same record text.
  const auto unpacked = run_command("zstd -dc '" + path("archive.din.zst") + "'");
  ASSERT_EQ(unpacked.exit_code, 0) << unpacked.err;
  EXPECT_EQ(unpacked.out, run_command("zstd -dc '" + path("default.din.zst") + "'").out);
  // The bytes do not depend on the thread count.
  archive.threads = 1;
  write_trace(path("archive1.din.zst"), records, archive, {}, markers);
  EXPECT_EQ(read_file(path("archive1.din.zst")), bytes);
}

TEST_F(Container, WindowLogIsTheDataFramesWindow) {
  WriterOptions small = options_for(RecordForm::Din, 1000);
  small.window_log = 12;  // 4 KiB, less than a data frame's 14 KB of text
  write_trace(path("w.din.zst"), sample_records(3000), small);
  auto reader = TraceReader::open(path("w.din.zst"));
  EXPECT_EQ(reader->header().json.at("compression").at("window_log"), 12);
  const std::string bytes = read_file(path("w.din.zst"));
  ASSERT_EQ(reader->trailer()->index.size(), 3u);
  for (const auto& entry : reader->trailer()->index) EXPECT_EQ(announced_window(bytes, entry.offset), 4096u);
  EXPECT_EQ(read_all(path("w.din.zst")).records, as_read_back(sample_records(3000), RecordForm::Din, true));
  // Windows zstd's decoders would refuse by default, or too small to exist.
  for (const unsigned bad : {9u, 28u}) {
    small.window_log = bad;
    EXPECT_THROW(TraceWriter::create(path("bad.din.zst"), {}, small), base::UsageError) << bad;
  }
}

TEST_F(Container, FramesWithLargeWindowsShareOneRingAndReadInOrder) {
  // Single-segment frames of 700,000 records: windows of 9.8 MB, above the
  // 8 MiB from which frames are decoded one at a time in one shared ring.
  WriterOptions archive = options_for(RecordForm::Din, 700000);
  archive.zstd_level = 1;
  archive.window_log = 26;
  const auto records = sample_records(2100000);
  write_trace(path("large.din.zst"), records, archive);
  const std::string bytes = read_file(path("large.din.zst"));
  auto reader = TraceReader::open(path("large.din.zst"));
  ASSERT_EQ(reader->trailer()->index.size(), 3u);
  for (const auto& entry : reader->trailer()->index) EXPECT_GT(announced_window(bytes, entry.offset), 8u << 20);
  EXPECT_EQ(read_all(path("large.din.zst")).records, as_read_back(records, RecordForm::Din, true));
}

TEST_F(Container, ConvertingAnArchiveDropsItsCompressionKey) {
  WriterOptions archive = options_for(RecordForm::Din, 1000);
  archive.window_log = 20;
  write_trace(path("a.din.zst"), sample_records(10), archive, {{"compression", "stale"}, {"producer", "unit"}});
  EXPECT_EQ(TraceReader::open(path("a.din.zst"))->header().json.at("compression").at("window_log"), 20);
  write_trace(path("b.din.zst"), sample_records(10), options_for(RecordForm::Din),
              TraceReader::open(path("a.din.zst"))->header().json);
  const auto header = TraceReader::open(path("b.din.zst"))->header().json;
  EXPECT_FALSE(header.contains("compression"));
  EXPECT_EQ(header.at("producer"), "unit");
}

TEST_F(Container, AddedTotalsReachTheTrailer) {
  auto writer = TraceWriter::create(path("t.din.zst"), {}, options_for(RecordForm::Din));
  writer->write(sample_records(5));
  writer->add_totals({{"rays", {{"primary", 12}}}});
  writer->finish();
  auto reader = TraceReader::open(path("t.din.zst"));
  EXPECT_EQ(reader->trailer()->totals.at("rays").at("primary"), 12);
  EXPECT_EQ(reader->trailer()->totals.at("records"), 5);
}

TEST_F(Container, WideAddressesAndHeaderChecks) {
  WriterOptions wide = options_for(RecordForm::Din);
  wide.address_digits = 16;
  const std::vector<Record> records = {{0x123456789abcull, 4, AccessType::Read, TraversalUnit{}, 3}, {0x10, 4, AccessType::Write, TraversalUnit{}, 4}};
  write_trace(path("w.din.zst"), records, wide);
  EXPECT_EQ(read_all(path("w.din.zst")).records, records);
  const auto text = run_command("zstd -dc '" + path("w.din.zst") + "'");
  EXPECT_EQ(text.out, "0 0000123456789abc 03\n1 0000000000000010 04\n");

  // A header from a future version, and a header that is not ours.
  const std::string future = R"({"container":{"name":"nodetrace-trace","version":2},"records":"din"})";
  std::string bytes("\x50\x2a\x4d\x18", 4);
  bytes += std::string(1, static_cast<char>(future.size())) + std::string(3, '\0') + future;
  write_file(path("f.din.zst"), bytes);
  EXPECT_NE(read_error(path("f.din.zst")).find("container version 2 is not one this reader knows"), std::string::npos)
      << read_error(path("f.din.zst"));
  const std::string other = R"({"records":"din"})";
  bytes = std::string("\x50\x2a\x4d\x18", 4) + std::string(1, static_cast<char>(other.size())) +
          std::string(3, '\0') + other;
  write_file(path("o.din.zst"), bytes);
  EXPECT_NE(read_error(path("o.din.zst")).find("header does not name the container"), std::string::npos);
  // Two containers glued together: a second header.
  const std::string one = read_file(path("w.din.zst"));
  write_file(path("two.din.zst"), one + one);
  EXPECT_NE(read_error(path("two.din.zst")), "");
}

// A small container with a header, markers, several data frames and a trailer.
std::string small_container(const std::string& file) {
  write_trace(file, sample_records(1200), options_for(RecordForm::Din, 200), {{"scene", "fuzz"}},
              {{0, marker(0)}, {600, marker(1)}});
  return read_file(file);
}

TEST_F(Container, EveryFlippedByteIsDetected) {
  const std::string original = small_container(path("t.din.zst"));
  ASSERT_EQ(read_error(path("t.din.zst")), "");
  int detected = 0, tried = 0;
  for (std::size_t at = 0; at < original.size(); at += 7) {
    std::string damaged = original;
    damaged[at] = static_cast<char>(damaged[at] ^ 0x10);
    write_file(path("d.din.zst"), damaged);
    ++tried;
    std::string message;
    try {
      read_all(path("d.din.zst"));
    } catch (const base::FormatError& error) {
      message = error.what();
    } catch (const base::UsageError& error) {
      message = error.what();
    }
    EXPECT_NE(message, "") << "flip at byte " << at << " went unnoticed";
    if (!message.empty()) ++detected;
    EXPECT_EQ(message.rfind(path("d.din.zst"), 0), 0u) << message;
  }
  EXPECT_EQ(detected, tried);
}

TEST_F(Container, DamagedHeaderMagicIsADamagedContainerByItsFooter) {
  const std::string original = small_container(path("t.din.zst"));
  // Every one-bit flip of the header magic, 0x50 -> 0x51..0x5F (still
  // skippable-frame magics, which zstd tools skip) included.
  for (std::size_t byte = 0; byte < 4; ++byte) {
    for (int bit = 0; bit < 8; ++bit) {
      std::string damaged = original;
      damaged[byte] = static_cast<char>(damaged[byte] ^ (1 << bit));
      write_file(path("d.din.zst"), damaged);
      const std::string message = read_error(path("d.din.zst"));
      EXPECT_EQ(message.rfind(path("d.din.zst") + ": damaged container: byte " + std::to_string(byte) + " is ", 0), 0u)
          << "byte " << byte << " bit " << bit << ": " << message;
    }
  }
  std::string damaged = original;
  damaged[0] = 0x5F;
  write_file(path("d.din.zst"), damaged);
  EXPECT_EQ(read_error(path("d.din.zst")),
            path("d.din.zst") +
                ": damaged container: byte 0 is 0x5f where the header magic 50 2A 4D 18 has 0x50 (the file ends with a "
                "container trailer)");
  // Through a pipe the footer is seen at the end of the stream.
  const auto piped = run_command("'" + program("tracetool").string() + "' verify - < '" + path("d.din.zst") + "'");
  EXPECT_EQ(piped.exit_code, 1);
  EXPECT_NE(piped.err.find("<stdin>: damaged container: byte 0 is 0x5f"), std::string::npos) << piped.err;
}

TEST_F(Container, DamagedTagKeyIsADamagedHeaderNotUntaggedRecords) {
  const std::string original = small_container(path("t.din.zst"));
  const std::size_t key = original.find("\"tag\":\"node-level\"");
  ASSERT_NE(key, std::string::npos);
  for (std::size_t at = key + 1; at < key + 4; ++at) {
    std::string damaged = original;
    damaged[at] = static_cast<char>(damaged[at] ^ 0x01);
    write_file(path("d.din.zst"), damaged);
    const std::string message = read_error(path("d.din.zst"));
    EXPECT_NE(message.find("damaged header: key "), std::string::npos) << message;
  }
  std::string damaged = original;
  damaged[key + 8] = static_cast<char>(damaged[key + 8] ^ 0x01);  // in "node-level"
  write_file(path("d.din.zst"), damaged);
  EXPECT_NE(read_error(path("d.din.zst")).find("damaged header: \"tag\" is \"nnde-level\""), std::string::npos)
      << read_error(path("d.din.zst"));
}

TEST_F(Container, TruncationIsDetected) {
  const std::string original = small_container(path("t.din.zst"));
  for (std::size_t keep = 0; keep < original.size(); keep += 13) {
    write_file(path("d.din.zst"), original.substr(0, keep));
    const std::string message = keep == 0 ? "empty" : read_error(path("d.din.zst"));
    EXPECT_NE(message, "") << "cut to " << keep << " bytes went unnoticed";
  }
  // Without its trailer, the header's promise is broken.
  auto reader = TraceReader::open(path("t.din.zst"));
  const auto trailer_start = reader->trailer()->index.back().offset + reader->trailer()->index.back().compressed_size;
  write_file(path("d.din.zst"), original.substr(0, trailer_start));
  EXPECT_NE(read_error(path("d.din.zst")).find("truncated"), std::string::npos) << read_error(path("d.din.zst"));
}

TEST_F(Container, FramesOutOfOrderAreNamed) {
  // Frames of identical records compress to the same size, so swapping two
  // keeps every offset right; only the order check can tell.
  std::vector<Record> records;
  for (int frame = 0; frame < 3; ++frame) {
    for (int i = 0; i < 100; ++i) records.push_back({0x1000u + 0x100u * frame, 4, AccessType::Read, TraversalUnit{}, 1});
  }
  write_trace(path("t.din.zst"), records, options_for(RecordForm::Din, 100));
  auto reader = TraceReader::open(path("t.din.zst"));
  const auto index = reader->trailer()->index;
  ASSERT_EQ(index.size(), 3u);
  ASSERT_EQ(index[0].compressed_size, index[1].compressed_size);
  std::string bytes = read_file(path("t.din.zst"));
  const std::string first = bytes.substr(index[0].offset, index[0].compressed_size);
  const std::string second = bytes.substr(index[1].offset, index[1].compressed_size);
  bytes.replace(index[0].offset, first.size(), second);
  bytes.replace(index[1].offset, second.size(), first);
  write_file(path("s.din.zst"), bytes);
  EXPECT_NE(read_error(path("s.din.zst")).find("data frame 1 at byte " + std::to_string(index[0].offset) +
                                               ": frame out of order: it is the index's data frame 2"),
            std::string::npos)
      << read_error(path("s.din.zst"));
}

TEST_F(Container, FuzzedInputNeverCrashes) {
  const std::string container = small_container(path("t.din.zst"));
  std::string text;
  for (int i = 0; i < 300; ++i) text += i % 3 ? "0 00001a38 07\n" : "r 1a38 8 p\n";
  std::uint64_t state = 12345;
  const auto next = [&] {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return state >> 33;
  };
  for (int round = 0; round < 400; ++round) {
    std::string input = round % 2 ? container : text;
    const int edits = 1 + static_cast<int>(next() % 4);
    for (int e = 0; e < edits && !input.empty(); ++e) {
      const std::size_t at = next() % input.size();
      switch (next() % 4) {
        case 0: input[at] = static_cast<char>(next()); break;
        case 1: input.erase(at, 1 + next() % 16); break;
        case 2: input.insert(at, std::string(1 + next() % 4, static_cast<char>(next()))); break;
        case 3: input.resize(at); break;
      }
    }
    write_file(path("f.in"), input);
    for (const bool levels : {false, true}) {
      ReaderOptions options;
      options.tags_are_levels = levels;
      options.threads = 1 + round % 2;
      try {
        read_all(path("f.in"), options);
      } catch (const base::FormatError&) {
      } catch (const base::UsageError&) {
      }
    }
  }
}

}  // namespace
}  // namespace nodetrace::formats
