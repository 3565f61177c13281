// Where a render's records go. The trace job (trace_job.hpp) feeds every
// sink of a layout the same calls, in order: per animation frame its marker,
// per sampled band its window marker, the records in trace order (already
// in that layout's addresses), and once the render is over, the totals.
// A trace writer is one sink; any other consumer of the records (a
// simulator, a counter) is another, plugged in the same way.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>

#include <nlohmann/json.hpp>

#include "nodetrace/formats/container/metadata.hpp"
#include "nodetrace/formats/record/record.hpp"
#include "nodetrace/tracer/render/layout_trace.hpp"

namespace nodetrace::tracer {

class RecordSink {
 public:
  virtual ~RecordSink() = default;
  virtual void begin_animation_frame(const formats::AnimationFrameMarker& marker) = 0;
  // A sampled band begins (only in row-sampled renders, after its animation frame's marker).
  virtual void begin_window(const formats::WindowMarker& marker) = 0;
  virtual void write(std::span<const formats::Record> records) = 0;
  // After the last record: what is known only once the render is over (the
  // ray-kind counts, node fetches, ...), the totals of a container's trailer.
  virtual void finish(const nlohmann::json& totals) = 0;
};

// One layout's trace as its sinks see it before its first record, once the
// first animation frame's tree is built.
struct TraceStart {
  std::size_t layout_index = 0;  // 0: the render's own layout; i: TraceJobOptions::other_layouts[i - 1]
  const LayoutTrace& layout;
  const nlohmann::json& header;  // the container header the trace of this layout carries
  // 8, or 16 when some stream's addresses can pass 32 bits.
  unsigned address_digits = 8;
};

// Makes the sink of one layout's records, or nullptr when it has none there.
using RecordSinkMaker = std::function<std::unique_ptr<RecordSink>(const TraceStart& start)>;

}  // namespace nodetrace::tracer
