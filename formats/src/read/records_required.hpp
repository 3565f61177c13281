// An input with no records is not a trace (internal; ReaderOptions::allow_empty).
#pragma once

#include <memory>
#include <string>

#include "nodetrace/formats/read/trace_reader.hpp"

namespace nodetrace::formats::detail {

// `reader`, whose next() throws base::FormatError at the end of the trace
// when it delivered no record and skipped no data frame.
std::unique_ptr<TraceReader> records_required(std::unique_ptr<TraceReader> reader);

// Throws the base::FormatError of an input `source_name` without records.
[[noreturn]] void fail_no_records(const std::string& source_name);

}  // namespace nodetrace::formats::detail
