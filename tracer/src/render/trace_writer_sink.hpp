// The record sink that writes a layout's trace file (formats::TraceWriter).
#pragma once

#include <memory>

#include "nodetrace/tracer/render/record_sink.hpp"
#include "nodetrace/tracer/render/trace_job.hpp"

namespace nodetrace::tracer {

// The trace writer of `start`'s layout, or nullptr when it names no file.
std::unique_ptr<RecordSink> make_trace_writer_sink(const TraceJobOptions& options, const TraceStart& start);

}  // namespace nodetrace::tracer
