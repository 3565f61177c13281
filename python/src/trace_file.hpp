// The objects of nodetrace.open(): an open trace and the iterator of its
// record batches.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "interruptible.hpp"
#include "record_array.hpp"
#include "nodetrace/formats/read/trace_reader.hpp"

namespace nodetrace::python {

// Walks a reader's records, carrying the animation frame of the last marker.
class RecordCursor {
 public:
  explicit RecordCursor(std::shared_ptr<formats::TraceReader> reader) : reader_(std::move(reader)) {}
  // Appends records until `out` holds `limit` or the trace ends; false when
  // it ended with nothing appended.
  // (RecordVector or RecordBuffer).
  template <class Records>
  bool fill(Records& out, std::size_t limit, const SignalCheck& stop);

 private:
  std::shared_ptr<formats::TraceReader> reader_;
  formats::RecordBatch batch_;
  bool ended_ = false;
  std::size_t used_ = 0;
  std::uint64_t frame_ = 0;
};

class RecordBatches {
 public:
  RecordBatches(std::shared_ptr<formats::TraceReader> reader, std::size_t records_per_batch)
      : cursor_(std::move(reader)), records_per_batch_(records_per_batch) {}
  pybind11::array next();

 private:
  RecordCursor cursor_;
  std::size_t records_per_batch_;
};

class TraceFile {
 public:
  TraceFile(std::string path, formats::ReaderOptions options);
  pybind11::array records();
  RecordBatches batches(std::size_t records_per_batch);
  pybind11::object header() const;
  pybind11::object trailer() const;
  const formats::TraceReader& reader() const { return *reader_; }
  const std::string& path() const { return path_; }
  // The reader simulate() consumes (the first, then one opened anew).
  std::shared_ptr<formats::TraceReader> fresh_reader();

 private:
  std::string path_;
  formats::ReaderOptions options_;
  std::shared_ptr<formats::TraceReader> reader_;
  bool reader_used_ = false;
};

void bind_trace_file(pybind11::module_& module);

}  // namespace nodetrace::python
