#include "trace_info_output.hpp"

#include <memory>
#include <utility>

#include "nodetrace/formats/write/trace_writer.hpp"
#include "nodetrace/base/output_file.hpp"

namespace nodetrace::tracer::tools {

namespace {

// Takes no records: writes its file when the render is over.
class TraceInfoSink final : public RecordSink {
 public:
  TraceInfoSink(std::string file, nlohmann::json header) : file_(std::move(file)), header_(std::move(header)) {}
  void begin_animation_frame(const formats::AnimationFrameMarker&) override {}
  void begin_window(const formats::WindowMarker&) override {}
  void write(std::span<const formats::Record>) override {}
  void finish(const nlohmann::json& totals) override {
    const nlohmann::json info = {{"header", header_}, {"totals", totals}};
    base::OutputFile file(file_);
    file.write(info.dump(2) + "\n");
    file.commit();
  }

 private:
  std::string file_;
  nlohmann::json header_;
};

}  // namespace

RecordSinkMaker trace_info_maker(std::vector<std::string> files) {
  return [files = std::move(files)](const TraceStart& start) -> std::unique_ptr<RecordSink> {
    return std::make_unique<TraceInfoSink>(files.at(start.layout_index),
                                           formats::container_header(start.header, start.writer));
  };
}

}  // namespace nodetrace::tracer::tools
