// What a whole read of a trace saw, counted the way a container's trailer
// counts its totals (FORMAT.md 2.4): records by tag and type, animation-frame
// and window markers. `tracetool verify` holds every total the trailer states
// to it; `tracetool info` reports it for a trace without a trailer.
#pragma once

#include <cstdint>

#include "nodetrace/formats/read/trace_reader.hpp"
#include "nodetrace/formats/record/record_summary.hpp"

namespace nodetrace::formats {

class ObservedTotals {
 public:
  // Call for every batch the reader delivers, in order.
  void add(const RecordBatch& batch) {
    markers_ += batch.marker.has_value();
    windows_ += batch.window.has_value();
    summary_.add(batch.records);
  }

  const RecordSummary& summary() const { return summary_; }
  std::uint64_t animation_frame_markers() const { return markers_; }
  std::uint64_t window_markers() const { return windows_; }

  // Compares each total the trailer of `reader` (read to its end) states
  // with what was seen: records, records_per_tag, records_per_type,
  // animation_frames, sample_windows, data_frames, record_bytes. Throws
  // base::FormatError naming the file and the first total that differs.
  // Keys a trailer leaves out are not checked (older traces lack some),
  // except sample_windows, which a writer leaves out when there are none.
  void check_trailer(const TraceReader& reader) const;

 private:
  RecordSummary summary_;
  std::uint64_t markers_ = 0;
  std::uint64_t windows_ = 0;
};

}  // namespace nodetrace::formats
