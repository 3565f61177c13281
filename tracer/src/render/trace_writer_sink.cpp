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

std::unique_ptr<RecordSink> make_trace_writer_sink(const TraceJobOptions& options, const TraceStart& start) {
  if (start.layout.output.empty()) return nullptr;
  formats::WriterOptions writer_options;
  writer_options.form = options.form;
  writer_options.threads = options.render.threads;
  writer_options.zstd_level = options.zstd_level;
  if (options.archive) formats::use_archive_setting(writer_options);
  writer_options.address_digits = start.address_digits;
  writer_options.units = options.render.units;
  return std::make_unique<TraceWriterSink>(formats::TraceWriter::create(start.layout.output, start.header, writer_options));
}

}  // namespace nodetrace::tracer
