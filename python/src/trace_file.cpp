// nodetrace.open(): a trace's header, trailer and records, read by
// formats::TraceReader (container, plain din / xdin / binary, zstd or not).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <algorithm>
#include <filesystem>
#include <cstdint>
#include <memory>
#include <span>
#include <optional>
#include <string>
#include <vector>

#include "interruptible.hpp"
#include "json_value.hpp"
#include "record_array.hpp"
#include "trace_file.hpp"
#include "nodetrace/base/error.hpp"
#include "nodetrace/base/huge_pages.hpp"
#include "nodetrace/formats/read/trace_reader.hpp"

namespace py = pybind11;

namespace nodetrace::python {

namespace {

formats::ReaderOptions reader_options(const std::optional<std::string>& informat, bool tags_are_levels,
                                      unsigned threads, bool check_record_hash) {
  formats::ReaderOptions options;
  if (informat) {
    options.form = formats::parse_form_name(*informat);
    if (!options.form) {
      throw base::UsageError("informat: expected din, xdin or binary, got '" + *informat + "'");
    }
  }
  options.tags_are_levels = tags_are_levels;
  options.threads = threads;
  options.check_record_hash = check_record_hash;
  // What the Python call names, in the hint for binary records read as text.
  options.binary_form_option = "informat='binary'";
  return options;
}

}  // namespace

TraceFile::TraceFile(std::string path, formats::ReaderOptions options)
    : path_(std::move(path)), options_(std::move(options)) {
  reader_ = formats::TraceReader::open(path_, options_);
}

std::shared_ptr<formats::TraceReader> TraceFile::fresh_reader() {
  if (!reader_used_) {
    reader_used_ = true;
    return reader_;
  }
  if (path_ == "-") throw base::UsageError("standard input: its records can be read once");
  reader_ = formats::TraceReader::open(path_, options_);
  return reader_;
}

template <class Records>
bool RecordCursor::fill(Records& out, std::size_t limit, const SignalCheck& stop) {
  while (out.size() < limit) {
    if (ended_) return out.size() != 0;
    if (used_ == batch_.records.size()) {
      stop();
      if (!reader_->next(batch_)) {
        // What next() leaves in the batch at the end is not records.
        ended_ = true;
        continue;
      }
      used_ = 0;
      if (batch_.marker) frame_ = batch_.marker->frame;
    }
    const std::size_t take = std::min(limit - out.size(), batch_.records.size() - used_);
    append_records(out, std::span(batch_.records).subspan(used_, take), frame_);
    used_ += take;
  }
  return true;
}

template bool RecordCursor::fill(RecordVector&, std::size_t, const SignalCheck&);
template bool RecordCursor::fill(RecordBuffer&, std::size_t, const SignalCheck&);

py::array TraceFile::records() {
  std::shared_ptr<formats::TraceReader> reader = fresh_reader();
  return to_array(run_interruptibly([&](const SignalCheck& stop) {
    // A container says how many: the array is mapped once, at its size;
    // otherwise it starts at 4096 records (a short trace maps little) and
    // doubles in place, at the cost of moving page tables.
    const auto& trailer = reader->trailer();
    const bool counted = trailer && trailer->totals.contains("records");
    auto out = std::make_unique<RecordBuffer>(counted ? trailer->totals["records"].get<std::uint64_t>()
                                                      : std::size_t{1} << 12);
    RecordCursor cursor(reader);
    cursor.fill(*out, SIZE_MAX, stop);
    return out;
  }));
}

RecordBatches TraceFile::batches(std::size_t records_per_batch) {
  if (records_per_batch == 0) throw base::UsageError("records_per_batch: expected at least 1");
  return RecordBatches(fresh_reader(), records_per_batch);
}

py::object TraceFile::header() const {
  return reader_->header().present() ? to_python(reader_->header().json) : py::none();
}

py::object TraceFile::trailer() const {
  return reader_->trailer() ? to_python(reader_->trailer()->to_json()) : py::none();
}

py::array RecordBatches::next() {
  RecordVector out;
  const bool any = run_interruptibly([&](const SignalCheck& stop) {
    base::reserve_on_huge_pages(out, records_per_batch_);
    return cursor_.fill(out, records_per_batch_, stop);
  });
  if (!any) throw py::stop_iteration();
  return to_array(std::move(out));
}

void bind_trace_file(py::module_& module) {
  py::class_<RecordBatches>(module, "RecordBatches",
                            "Iterator over a trace's records, a structured array of at most records_per_batch "
                            "records at a time (the last may hold fewer).")
      .def("__iter__", [](py::object self) { return self; })
      .def("__next__", &RecordBatches::next);

  py::class_<TraceFile>(module, "TraceFile", "An open trace; see nodetrace.open.")
      .def_property_readonly("header", &TraceFile::header,
                             "The container's header JSON as a dict; None for a plain trace.")
      .def_property_readonly("trailer", &TraceFile::trailer,
                             "The container's trailer JSON as a dict (index, totals, record_hash, content_hash); "
                             "None for a plain trace, and for a container read from a pipe until its records "
                             "have been read.")
      .def_property_readonly("form", [](const TraceFile& self) { return std::string(formats::form_name(self.reader().form())); },
                             "Record form: din, xdin or binary.")
      .def_property_readonly("tags_are_levels", [](const TraceFile& self) { return self.reader().tags_are_levels(); })
      .def_property_readonly("units", [](const TraceFile& self) { return self.reader().units(); })
      .def_property_readonly("input_kind", [](const TraceFile& self) { return std::string(self.reader().input_kind()); },
                             "container, zstd (a plain zstd stream) or plain.")
      .def("records", &TraceFile::records,
           "All records as one structured array (nodetrace.RECORD_DTYPE: address, size, kind, unit, level, "
           "frame). Raises nodetrace.FormatError on bad or damaged data, returning nothing.")
      // 65536 records (1.5 MiB) a batch by default: small enough that each
      // batch's memory is reused from the heap rather than fresh pages the
      // kernel zeroes (measured on Kitchen 400x300: batches of 1M records
      // cost about 1.25x the CPU of batches of 64K).
      .def("batches", &TraceFile::batches, py::arg("records_per_batch") = 1 << 16, py::keep_alive<0, 1>(),
           "Iterates over the records in structured arrays of at most records_per_batch records, for traces "
           "larger than memory.");

  module.def(
      "open",
      [](const std::filesystem::path& path, std::optional<std::string> informat, bool tags_are_levels,
         unsigned threads, bool check_record_hash) {
        return TraceFile(path.string(), reader_options(informat, tags_are_levels, threads, check_record_hash));
      },
      py::arg("path"), py::arg("informat") = py::none(), py::arg("tags_are_levels") = false, py::arg("threads") = 0,
      py::arg("check_record_hash") = false,
      "Opens a trace: a container (.din.zst, .xdin.zst), plain din / xdin / binary text, a plain zstd stream, or "
      "'-' for standard input. informat names a plain trace's record form (din, xdin, binary; default: from the "
      "file name, else from the first record); tags_are_levels reads a plain trace's tags as node levels; "
      "threads decode (0: one per core); check_record_hash also checks a container's record hash, a pass over all "
      "the text (damage is caught without it, as cachesim run reads; tracetool verify checks it). Raises OSError when the file cannot be read, nodetrace.FormatError "
      "when it is not a trace.");
}

}  // namespace nodetrace::python
