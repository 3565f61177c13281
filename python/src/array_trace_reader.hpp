// Records given as a numpy array (nodetrace.RECORD_DTYPE) read as a trace,
// so that simulate() runs on them what it runs on a file: extended din
// (each record keeps its address and size), tags read as node levels, an
// animation-frame marker wherever the frame field changes (none when it
// never does: one animation frame, as a trace without markers), the units
// the unit field gives. The array is held, not copied; batches are cut from
// it as the reader's are.
#pragma once

#include <pybind11/numpy.h>

#include <algorithm>
#include <cstdint>
#include <optional>
#include <string>

#include "record_array.hpp"
#include "nodetrace/base/error.hpp"
#include "nodetrace/formats/read/trace_reader.hpp"

namespace nodetrace::python {

class ArrayTraceReader final : public formats::TraceReader {
 public:
  // Call with the GIL held; `records` must stay alive (the caller holds it).
  ArrayTraceReader(const pybind11::array_t<ArrayRecord>& records, std::string name)
      : name_(std::move(name)), records_(records.data()), count_(static_cast<std::size_t>(records.size())) {
    std::uint8_t top_unit = 0;
    for (std::size_t i = 0; i < count_; ++i) {
      top_unit = std::max(top_unit, records_[i].unit);
      if (records_[i].frame != records_[0].frame) frames_vary_ = true;
    }
    units_ = top_unit + 1u;
    if (units_ > 1) header_.json["units"] = units_;
  }

  const std::string& source_name() const override { return name_; }
  const formats::TraceHeader& header() const override { return header_; }
  formats::RecordForm form() const override { return formats::RecordForm::ExtendedDin; }
  bool tags_are_levels() const override { return true; }
  unsigned units() const override { return units_; }
  const std::optional<formats::TraceTrailer>& trailer() const override { return trailer_; }
  void seek_to_record(std::uint64_t) override {
    throw base::UsageError(name_ + ": records given as an array cannot seek");
  }

  bool next(formats::RecordBatch& batch) override {
    if (next_ == count_) return false;
    batch.marker.reset();
    batch.window.reset();
    batch.first_record = next_;
    const std::uint64_t frame = records_[next_].frame;
    if (frames_vary_ && (next_ == 0 || records_[next_ - 1].frame != frame)) {
      batch.marker = formats::AnimationFrameMarker{};
      batch.marker->frame = frame;
    }
    // Up to a batch's worth, and not past the end of the animation frame.
    std::size_t end = next_;
    const std::size_t limit = std::min(count_, next_ + kBatchRecords);
    while (end < limit && records_[end].frame == frame) ++end;
    batch.records.resize(end - next_);
    for (std::size_t i = next_; i < end; ++i) batch.records[i - next_] = to_record(records_[i]);
    batch.kinds = formats::record_kinds(batch.records.data(), batch.records.size());
    next_ = end;
    return true;
  }

 private:
  static constexpr std::size_t kBatchRecords = 1 << 16;
  std::string name_;
  const ArrayRecord* records_;
  std::size_t count_;
  std::size_t next_ = 0;
  bool frames_vary_ = false;
  unsigned units_ = 1;
  formats::TraceHeader header_;
  std::optional<formats::TraceTrailer> trailer_;
};

}  // namespace nodetrace::python
