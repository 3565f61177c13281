// Sample windows (the sampling contract): window markers round-trip in order
// with animation-frame markers in every output kind, the header's "sampling"
// key, and keep_data_frame skipping data frames of a seekable container
// without reading or decompressing them (streams deliver everything).
#include <gtest/gtest.h>

#include "formats_test_util.hpp"
#include "test_support.hpp"

namespace nodetrace::formats {
namespace {

using nodetrace::testing::read_file;
using nodetrace::testing::run_command;
using nodetrace::testing::shell_quoted;
using nodetrace::testing::TempDir;
using nodetrace::testing::write_file;
using testing_util::sample_records;

// One marker as written or read: 'F' animation frame, 'W' sample window.
struct Event {
  std::uint64_t record = 0;
  char kind = 'F';
  std::uint64_t number = 0;  // frame number, or window number
  nlohmann::json json;       // the marker's whole JSON

  friend bool operator==(const Event&, const Event&) = default;
};

void PrintTo(const Event& event, std::ostream* out) {
  *out << event.kind << event.number << "@" << event.record << " " << event.json.dump();
}

AnimationFrameMarker frame_marker(std::uint64_t frame) {
  AnimationFrameMarker marker;
  marker.frame = frame;
  marker.nodes_per_level = {1, 2};
  marker.nodes = 3;
  marker.leaves = 2;
  marker.depth = 2;
  return marker;
}

WindowMarker window_marker(std::uint64_t window, std::uint64_t frame) {
  WindowMarker marker;
  marker.window = window;
  marker.frame = frame;
  marker.extra["rows"] = {window * 4, window * 4 + 4};
  return marker;
}

Event frame_event(std::uint64_t record, std::uint64_t frame) {
  return {record, 'F', frame, frame_marker(frame).to_json()};
}
Event window_event(std::uint64_t record, std::uint64_t window, std::uint64_t frame) {
  return {record, 'W', window, window_marker(window, frame).to_json()};
}

// Writes `records` with `events` (in call order; an event at record r is
// called before record r is written).
void write_with_events(const std::string& path, const std::vector<Record>& records, const std::vector<Event>& events,
                       const WriterOptions& options) {
  auto writer = TraceWriter::create(path, nlohmann::json::object(), options);
  std::size_t next = 0;
  for (std::size_t i = 0; i <= records.size(); ++i) {
    for (; next < events.size() && events[next].record == i; ++next) {
      if (events[next].kind == 'F') {
        writer->begin_animation_frame(AnimationFrameMarker::from_json(events[next].json));
      } else {
        writer->begin_window(WindowMarker::from_json(events[next].json));
      }
    }
    if (i < records.size()) writer->write(records[i]);
  }
  writer->finish();
}

struct Read {
  std::vector<Record> records;
  std::vector<Event> events;
  std::vector<std::uint64_t> batch_starts;  // first_record of each batch with records
  std::uint64_t decompressed = 0;
  std::uint64_t skipped = 0;
};

Read read_events(const std::string& path, const ReaderOptions& options = {}) {
  auto reader = TraceReader::open(path, options);
  Read result;
  RecordBatch batch;
  while (reader->next(batch)) {
    if (batch.marker) result.events.push_back({batch.first_record, 'F', batch.marker->frame, batch.marker->to_json()});
    if (batch.window) {
      result.events.push_back({batch.first_record, 'W', batch.window->window, batch.window->to_json()});
    }
    if (!batch.records.empty()) result.batch_starts.push_back(batch.first_record);
    result.records.insert(result.records.end(), batch.records.begin(), batch.records.end());
  }
  result.decompressed = reader->data_frames_decompressed();
  result.skipped = reader->data_frames_skipped();
  return result;
}

// read_events on standard input fed `bytes` through a pipe.
Read read_events_from_stdin(const std::string& bytes, const ReaderOptions& options = {}) {
  Read result;
  EXPECT_EQ(testing_util::with_stdin_from(bytes, [&] { result = read_events("-", options); }), "");
  return result;
}

WriterOptions options_for(RecordForm form, OutputKind kind = OutputKind::Auto) {
  WriterOptions options;
  options.form = form;
  options.kind = kind;
  options.records_per_data_frame = 250;
  options.threads = 2;
  return options;
}

// Frame then window at one record, an empty window, a window ended by the
// next animation frame, a window cut by no data-frame boundary, and a window
// with no records at the end.
std::vector<Event> mixed_events() {
  return {frame_event(0, 0),      window_event(0, 0, 0),   window_event(300, 1, 0),
          window_event(300, 2, 0), window_event(777, 3, 0), frame_event(1000, 1),
          window_event(1000, 0, 1), window_event(1400, 1, 1), frame_event(1500, 2),
          window_event(1500, 0, 2), window_event(2000, 1, 2)};
}

class SampleWindows : public ::testing::Test {
 protected:
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  TempDir dir_;
};

TEST_F(SampleWindows, WindowMarkersRoundTripInOrderWithFrameMarkersInEveryForm) {
  const auto records = sample_records(2000);
  const auto events = mixed_events();
  for (const RecordForm form : {RecordForm::Din, RecordForm::ExtendedDin, RecordForm::Binary}) {
    SCOPED_TRACE(std::string(form_name(form)));
    const std::string file = path("t." + std::string(form_name(form)) + ".zst");
    write_with_events(file, records, events, options_for(form));
    const Read read = read_events(file);
    EXPECT_EQ(read.events, events);
    EXPECT_EQ(read.records.size(), records.size());
    auto reader = TraceReader::open(file);
    ASSERT_TRUE(reader->trailer());
    EXPECT_EQ(reader->trailer()->totals.at("sample_windows"), 8);
    EXPECT_EQ(reader->trailer()->totals.at("animation_frames"), 3);
  }
}

TEST_F(SampleWindows, WindowMarkersArriveInOrderThroughAPipe) {
  const auto records = sample_records(2000);
  const auto events = mixed_events();
  write_with_events(path("t.din.zst"), records, events, options_for(RecordForm::Din));
  const Read read = read_events_from_stdin(read_file(path("t.din.zst")));
  EXPECT_EQ(read.events, events);
  EXPECT_EQ(read.records.size(), records.size());
}

TEST_F(SampleWindows, ContainerUnderAnyNameCarriesWindowMarkers) {
  const auto records = sample_records(600);
  const std::vector<Event> events = {frame_event(0, 0), window_event(0, 0, 0), window_event(400, 1, 0)};
  write_with_events(path("auto.din.zst"), records, events, options_for(RecordForm::Din));
  EXPECT_EQ(read_events(path("auto.din.zst")).events, events);
  // OutputKind::Container under a name without .zst: the same bytes.
  write_with_events(path("named.din"), records, events, options_for(RecordForm::Din, OutputKind::Container));
  EXPECT_EQ(read_events(path("named.din")).events, events);
  EXPECT_EQ(read_file(path("named.din")), read_file(path("auto.din.zst")));
}

TEST_F(SampleWindows, PlainOutputWritesNoWindowMarkers) {
  const auto records = sample_records(2000);
  for (const RecordForm form : {RecordForm::Din, RecordForm::ExtendedDin, RecordForm::Binary}) {
    SCOPED_TRACE(std::string(form_name(form)));
    write_with_events(path("with"), records, mixed_events(), options_for(form, OutputKind::Plain));
    write_with_events(path("without"), records, {}, options_for(form, OutputKind::Plain));
    EXPECT_EQ(read_file(path("with")), read_file(path("without")));
  }
  // OutputKind::Auto on a name without .zst is plain output too.
  write_with_events(path("t.xdin"), records, mixed_events(), options_for(RecordForm::ExtendedDin));
  write_with_events(path("u.xdin"), records, {}, options_for(RecordForm::ExtendedDin));
  EXPECT_EQ(read_file(path("t.xdin")), read_file(path("u.xdin")));
  EXPECT_TRUE(read_events(path("t.xdin")).events.empty());
}

TEST_F(SampleWindows, ZstdToolSkipsWindowMarkers) {
  const auto records = sample_records(1000);
  write_with_events(path("t.din.zst"), records, mixed_events(), options_for(RecordForm::Din));
  write_with_events(path("t.din"), records, {}, options_for(RecordForm::Din));
  const auto result = run_command("zstd -dc " + shell_quoted(path("t.din.zst")));
  ASSERT_EQ(result.exit_code, 0);
  EXPECT_EQ(result.out, read_file(path("t.din")));
}

TEST_F(SampleWindows, MarkerJsonIsCheckedAndKept) {
  const WindowMarker marker = WindowMarker::from_json(nlohmann::json::parse(R"({"window": 7, "frame": 2, "rows": [28, 32]})"));
  EXPECT_EQ(marker.window, 7u);
  EXPECT_EQ(marker.frame, 2u);
  EXPECT_EQ(marker.extra.dump(), R"({"rows":[28,32]})");
  EXPECT_EQ(marker.to_json().dump(), R"({"frame":2,"rows":[28,32],"window":7})");
  EXPECT_THROW(WindowMarker::from_json(nlohmann::json::parse(R"({"frame": 2})")), base::FormatError);
  EXPECT_THROW(WindowMarker::from_json(nlohmann::json::parse(R"({"window": -1, "frame": 2})")), base::FormatError);
  EXPECT_THROW(WindowMarker::from_json(nlohmann::json::parse(R"({"window": 1})")), base::FormatError);
  EXPECT_THROW(WindowMarker::from_json(nlohmann::json::array()), base::FormatError);
}

TEST_F(SampleWindows, HeaderSamplingKeyIsTyped) {
  SamplingInfo info;
  info.method = "rows";
  info.every = 16;
  info.band_height = 4;
  info.seed = 9;
  info.bands = 150;
  info.extra["note"] = "kept";
  WriterOptions options = options_for(RecordForm::Din);
  {
    auto writer = TraceWriter::create(path("s.din.zst"), {{"sampling", info.to_json()}}, options);
    writer->write(sample_records(10));
    writer->finish();
  }
  auto reader = TraceReader::open(path("s.din.zst"));
  const auto sampling = reader->header().sampling();
  ASSERT_TRUE(sampling);
  EXPECT_EQ(sampling->method, "rows");
  EXPECT_EQ(sampling->every, 16u);
  EXPECT_EQ(sampling->band_height, 4u);
  EXPECT_EQ(sampling->seed, 9u);
  EXPECT_EQ(sampling->bands, 150u);
  EXPECT_EQ(sampling->extra, (nlohmann::json{{"note", "kept"}}));
  EXPECT_FALSE(TraceHeader{}.sampling());
  EXPECT_FALSE((TraceHeader{{{"records", "din"}}}.sampling()));
  const auto header = [](const char* json) { return TraceHeader{nlohmann::json::parse(json)}; };
  EXPECT_THROW(header(R"({"sampling": {"every": 2}})").sampling(), base::FormatError);  // no method
  EXPECT_THROW(header(R"({"sampling": {"method": "rows", "every": 0}})").sampling(), base::FormatError);
  EXPECT_THROW(header(R"({"sampling": {"method": "rows", "seed": "x"}})").sampling(), base::FormatError);
  EXPECT_THROW(header(R"({"sampling": 3})").sampling(), base::FormatError);
  EXPECT_EQ(header(R"({"sampling": {"method": "rows"}})").sampling()->every, 1u);
}

// 10 data frames of 1000 records; windows every 2000 records, animation
// frames at 0 and 5000 (data frame 5, which the filter below skips).
std::vector<Event> skipping_events() {
  return {frame_event(0, 0),        window_event(0, 0, 0),    window_event(2000, 1, 0), window_event(4000, 2, 0),
          frame_event(5000, 1),     window_event(5000, 0, 1), window_event(7000, 1, 1), window_event(9000, 2, 1),
          window_event(10000, 3, 1)};
}

// sample_records(10000) as xdin (read back exactly), with skipping_events().
std::vector<Record> write_skipping_trace(const std::string& path) {
  auto records = sample_records(10000);
  WriterOptions options = options_for(RecordForm::ExtendedDin);
  options.records_per_data_frame = 1000;
  write_with_events(path, records, skipping_events(), options);
  return records;
}

ReaderOptions every_other_frame() {
  ReaderOptions options;
  options.keep_data_frame = [](const DataFrameIndexEntry& entry) { return (entry.first_record / 1000) % 2 == 0; };
  return options;
}

TEST_F(SampleWindows, KeepDataFrameDeliversExactlyTheKeptFramesAndEveryMarker) {
  const auto records = write_skipping_trace(path("t.xdin.zst"));
  const Read full = read_events(path("t.xdin.zst"));
  ASSERT_EQ(full.events, skipping_events());
  EXPECT_EQ(full.decompressed, 10u);
  EXPECT_EQ(full.skipped, 0u);

  const Read kept = read_events(path("t.xdin.zst"), every_other_frame());
  EXPECT_EQ(kept.events, skipping_events());
  EXPECT_EQ(kept.batch_starts, (std::vector<std::uint64_t>{0, 2000, 4000, 6000, 8000}));
  std::vector<Record> expected;
  for (std::size_t start = 0; start < records.size(); start += 2000) {
    expected.insert(expected.end(), records.begin() + static_cast<long>(start),
                    records.begin() + static_cast<long>(start + 1000));
  }
  EXPECT_EQ(kept.records, expected);
  EXPECT_EQ(kept.decompressed, 5u);
  EXPECT_EQ(kept.skipped, 5u);
}

// Reading on to the trailer after the last data frame (kept or skipped)
// must not look past the index (a sampled run at 1/1 keeps every frame).
// 8 data frames: the index vector's capacity is then its size, so a sanitizer
// build sees a read one past its end.
TEST_F(SampleWindows, KeepDataFrameKeepingEveryFrameOrOnlyTheLastReadsOnToTheTrailer) {
  const auto records = sample_records(8000);
  WriterOptions options = options_for(RecordForm::ExtendedDin);
  options.records_per_data_frame = 1000;
  const std::vector<Event> events = {frame_event(0, 0), window_event(8000, 1, 0)};
  write_with_events(path("t.xdin.zst"), records, events, options);

  ReaderOptions every;
  every.keep_data_frame = [](const DataFrameIndexEntry&) { return true; };
  const Read all = read_events(path("t.xdin.zst"), every);
  EXPECT_EQ(all.events, events);
  EXPECT_EQ(all.records, records);
  EXPECT_EQ(all.decompressed, 8u);
  EXPECT_EQ(all.skipped, 0u);

  ReaderOptions last;
  last.keep_data_frame = [](const DataFrameIndexEntry& entry) { return entry.first_record == 7000; };
  const Read only_last = read_events(path("t.xdin.zst"), last);
  EXPECT_EQ(only_last.events, events);
  EXPECT_EQ(only_last.records, std::vector<Record>(records.begin() + 7000, records.end()));
  EXPECT_EQ(only_last.decompressed, 1u);
  EXPECT_EQ(only_last.skipped, 7u);
}

TEST_F(SampleWindows, SkippedDataFramesAreNotReadButKeptOnesAreChecked) {
  const auto records = write_skipping_trace(path("t.xdin.zst"));
  auto reader = TraceReader::open(path("t.xdin.zst"));
  const auto index = reader->trailer()->index;
  ASSERT_EQ(index.size(), 10u);
  const std::string bytes = read_file(path("t.xdin.zst"));
  const auto damaged_in = [&](std::size_t frame) {
    std::string copy = bytes;
    copy[index[frame].offset + index[frame].compressed_size / 2] ^= 0x40;
    const std::string name = path("damaged" + std::to_string(frame) + ".xdin.zst");
    write_file(name, copy);
    return name;
  };
  // Damage in a skipped data frame goes unseen: its bytes were never read.
  const std::string in_skipped = damaged_in(3);
  EXPECT_NE(testing_util::read_error(in_skipped), "");
  Read read;
  EXPECT_NO_THROW(read = read_events(in_skipped, every_other_frame()));
  EXPECT_EQ(read.decompressed, 5u);
  EXPECT_EQ(read.skipped, 5u);
  // Damage in a kept data frame is found.
  const std::string in_kept = damaged_in(4);
  EXPECT_THROW(read_events(in_kept, every_other_frame()), base::FormatError);
}

TEST_F(SampleWindows, KeepDataFrameIsIgnoredOnStreams) {
  const auto records = write_skipping_trace(path("t.xdin.zst"));
  // A container on standard input cannot seek: everything is delivered.
  const Read piped = read_events_from_stdin(read_file(path("t.xdin.zst")), every_other_frame());
  EXPECT_EQ(piped.events, skipping_events());
  EXPECT_EQ(piped.records.size(), records.size());
  EXPECT_EQ(piped.decompressed, 10u);
  EXPECT_EQ(piped.skipped, 0u);
  // Plain zstd (no index): everything is delivered.
  write_with_events(path("t.xdin"), records, {}, options_for(RecordForm::ExtendedDin));
  ASSERT_EQ(
      run_command("zstd -q -c " + shell_quoted(path("t.xdin")) + " > " + shell_quoted(path("p.xdin.zst"))).exit_code, 0);
  ReaderOptions plain = every_other_frame();
  plain.tags_are_levels = true;
  const Read zstd = read_events(path("p.xdin.zst"), plain);
  EXPECT_EQ(zstd.records, records);
  EXPECT_EQ(zstd.skipped, 0u);
}

TEST_F(SampleWindows, SeekingStillWorksWithSkipping) {
  const auto records = write_skipping_trace(path("t.xdin.zst"));
  auto reader = TraceReader::open(path("t.xdin.zst"), every_other_frame());
  reader->seek_to_record(6500);
  RecordBatch batch;
  ASSERT_TRUE(reader->next(batch));
  EXPECT_EQ(batch.first_record, 6000u);
  ASSERT_EQ(batch.records.size(), 1000u);
  EXPECT_EQ(batch.records[500], records[6500]);
}

TEST_F(SampleWindows, TracetoolConvertKeepsWindowMarkers) {
  const auto records = sample_records(2000);
  write_with_events(path("t.din.zst"), records, mixed_events(), options_for(RecordForm::Din));
  const auto result = run_command(shell_quoted(nodetrace::testing::program("tracetool")) + " convert --to xdin " +
                                  shell_quoted(path("t.din.zst")) + " " + shell_quoted(path("t.xdin.zst")));
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_EQ(read_events(path("t.xdin.zst")).events, mixed_events());
}

}  // namespace
}  // namespace nodetrace::formats
