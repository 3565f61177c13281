#include "render/trace_writer_sink.hpp"

#include <utility>

#include "nodetrace/formats/write/trace_writer.hpp"

namespace nodetrace::tracer {

namespace {

class TraceWriterSink final : public RecordSink {
 public:
  explicit TraceWriterSink(std::unique_ptr<formats::TraceWriter> writer) : writer_(std::move(writer)) {}
  void begin_animation_frame(const formats::AnimationFrameMarker& marker) override {
    writer_->begin_animation_frame(marker);
  }
  void begin_window(const formats::WindowMarker& marker) override { writer_->begin_window(marker); }
  void write(std::span<const formats::Record> records) override { writer_->write(records); }
  void finish(const nlohmann::json& totals) override {
    writer_->add_totals(totals);
    writer_->finish();
  }

 private:
  std::unique_ptr<formats::TraceWriter> writer_;
};

}  // namespace

std::unique_ptr<RecordSink> make_trace_writer_sink(const TraceStart& start) {
  if (start.layout.output.empty()) return nullptr;
  return std::make_unique<TraceWriterSink>(formats::TraceWriter::create(start.layout.output, start.header, start.writer));
}

}  // namespace nodetrace::tracer
