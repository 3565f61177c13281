// Record sinks: a sink a caller adds to the trace job gets, for each layout,
// exactly what that layout's trace file holds: its header, its animation
// frames' markers and window markers, its records in order, and the totals.
#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

#include "nodetrace/formats/read/trace_reader.hpp"
#include "nodetrace/tracer/render/trace_job.hpp"
#include "nodetrace/tracer/scene/scene_loader.hpp"
#include "test_support.hpp"

namespace nodetrace::tracer {
namespace {

using nodetrace::testing::TempDir;

// What one sink was given, call by call.
struct SinkLog {
  std::size_t layout_index = 0;
  nlohmann::json header;
  std::vector<std::uint64_t> frames;   // animation-frame markers' numbers
  std::vector<std::uint64_t> windows;  // window markers' numbers
  std::vector<formats::Record> records;
  nlohmann::json totals;
  int finished = 0;
};

class LoggingSink final : public RecordSink {
 public:
  explicit LoggingSink(SinkLog& log) : log_(log) {}
  void begin_animation_frame(const formats::AnimationFrameMarker& marker) override {
    log_.frames.push_back(marker.frame);
  }
  void begin_window(const formats::WindowMarker& marker) override { log_.windows.push_back(marker.window); }
  void write(std::span<const formats::Record> records) override {
    log_.records.insert(log_.records.end(), records.begin(), records.end());
  }
  void finish(const nlohmann::json& totals) override {
    log_.totals = totals;
    ++log_.finished;
  }

 private:
  SinkLog& log_;
};

// The job's options with a logging sink on every layout, the logs in `logs`.
void add_logging_sinks(TraceJobOptions& options, std::vector<std::unique_ptr<SinkLog>>& logs) {
  options.sink_makers.push_back([&logs](const TraceStart& start) -> std::unique_ptr<RecordSink> {
    logs.push_back(std::make_unique<SinkLog>());
    logs.back()->layout_index = start.layout_index;
    logs.back()->header = start.header;
    return std::make_unique<LoggingSink>(*logs.back());
  });
}

// The trace's records, animation-frame and window numbers.
void read_trace(const std::string& path, SinkLog& log) {
  auto reader = formats::TraceReader::open(path);
  log.header = reader->header().json;
  formats::RecordBatch batch;
  while (reader->next(batch)) {
    if (batch.marker) log.frames.push_back(batch.marker->frame);
    if (batch.window) log.windows.push_back(batch.window->window);
    log.records.insert(log.records.end(), batch.records.begin(), batch.records.end());
  }
  log.totals = reader->trailer()->totals;
}

void expect_sink_saw_its_trace(const SinkLog& sink, const std::string& path) {
  SinkLog file;
  read_trace(path, file);
  ASSERT_GT(file.records.size(), 100u);
  EXPECT_EQ(sink.finished, 1);
  EXPECT_EQ(sink.frames, file.frames);
  EXPECT_EQ(sink.windows, file.windows);
  ASSERT_EQ(sink.records.size(), file.records.size());
  // Din carries no size: its readers give every record Dinero IV's 4 bytes.
  std::vector<formats::Record> written = sink.records;
  if (file.header.at("records") == "din") {
    for (auto& record : written) record.size = 4;
  }
  EXPECT_TRUE(written == file.records) << path;
  // The writer adds the container's own keys; every key the sink was given is the file's.
  for (const auto& [key, value] : sink.header.items()) EXPECT_EQ(file.header.at(key), value) << key;
  for (const auto& [key, value] : sink.totals.items()) EXPECT_EQ(file.totals.at(key), value) << key;
}

TraceJobOptions small_render(const TempDir& dir) {
  TraceJobOptions options;
  options.render.width = 24;
  options.render.height = 16;
  options.render.threads = 2;
  options.layout = LayoutKind::Hybrid;
  options.split_level = 3;
  options.output = (dir / "hybrid.din.zst").string();
  options.other_layouts.push_back({LayoutKind::Bfl, std::nullopt, std::nullopt, (dir / "bfl.din.zst").string()});
  return options;
}

// A scene of two animation frames whose trees differ: a moving square of
// triangles before a grid of them.
std::string moving_scene(const TempDir& dir) {
  std::string scene = "a 0 1 2\nx mover { p 3  0 0 0  1 0 0  0 1 0 }\nl 0 0 5\n";
  for (int i = 0; i < 10; ++i) {
    for (int j = 0; j < 10; ++j) {
      const std::string x = std::to_string(i), y = std::to_string(j);
      scene += "p 3  " + x + " " + y + " -2  " + std::to_string(i + 1) + " " + y + " -2  " + x + " " +
               std::to_string(j + 1) + " -1.5\n";
    }
  }
  scene += "k mover {\n transl 2\n 0  0 0 0  0 0 0\n 1  5 5 1  0 0 0\n}\n";
  const auto path = dir / "moving.aff";
  nodetrace::testing::write_file(path, scene);
  return path.string();
}

TEST(RecordSinks, EachLayoutsSinkGetsWhatItsTraceFileHolds) {
  TempDir dir;
  TraceJobOptions options = small_render(dir);
  options.frames = {0, 1, 1};  // both animation frames
  std::vector<std::unique_ptr<SinkLog>> logs;
  add_logging_sinks(options, logs);
  const auto source = open_scene(moving_scene(dir));
  run_trace_job(*source, options);
  ASSERT_EQ(logs.size(), 2u);
  EXPECT_EQ(logs[0]->layout_index, 0u);
  EXPECT_EQ(logs[1]->layout_index, 1u);
  EXPECT_EQ(logs[0]->frames.size(), 2u);
  expect_sink_saw_its_trace(*logs[0], options.output);
  expect_sink_saw_its_trace(*logs[1], options.other_layouts[0].output);
}

TEST(RecordSinks, SampledRenderGivesEverySinkTheWindowMarkers) {
  TempDir dir;
  TraceJobOptions options = small_render(dir);
  options.sampling = RowSampling{4, 2, 7};
  std::vector<std::unique_ptr<SinkLog>> logs;
  add_logging_sinks(options, logs);
  run_trace_job(*open_scene("mountain:6"), options);
  ASSERT_EQ(logs.size(), 2u);
  EXPECT_FALSE(logs[0]->windows.empty());
  expect_sink_saw_its_trace(*logs[0], options.output);
  expect_sink_saw_its_trace(*logs[1], options.other_layouts[0].output);
}

TEST(RecordSinks, SinksWithoutTraceFilesGetTheRecordsAFileWouldHold) {
  TempDir dir;
  TraceJobOptions with_files = small_render(dir);
  std::vector<std::unique_ptr<SinkLog>> logs;
  TraceJobOptions without = small_render(dir);
  without.output.clear();
  without.other_layouts.clear();
  add_logging_sinks(without, logs);
  run_trace_job(*open_scene("mountain:6"), with_files);
  run_trace_job(*open_scene("mountain:6"), without);
  ASSERT_EQ(logs.size(), 1u);
  expect_sink_saw_its_trace(*logs[0], with_files.output);
}

}  // namespace
}  // namespace nodetrace::tracer
