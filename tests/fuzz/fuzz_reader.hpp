// The body of the trace-reader targets: every input must read cleanly or be
// rejected with FormatError (exit 1 in every front end). Any other exception,
// UsageError (exit 2) included, escapes and is reported as a crash.
#pragma once

#include <optional>

#include "fuzz_support.hpp"
#include "nodetrace/base/error.hpp"
#include "nodetrace/formats/read/trace_reader.hpp"

namespace nodetrace::fuzz {

inline void read_trace(std::string_view bytes, std::optional<formats::RecordForm> form, bool tags_are_levels) {
  const MemoryFile file(bytes);
  formats::ReaderOptions options;
  options.form = form;
  options.tags_are_levels = tags_are_levels;
  options.threads = 1;
  try {
    auto reader = formats::TraceReader::open(file.path(), options);
    formats::RecordBatch batch;
    std::uint64_t records = 0;
    while (reader->next(batch)) records += batch.records.size();
    // A container that read cleanly can be sought in by its index.
    if (reader->trailer() && records > 0) {
      auto again = formats::TraceReader::open(file.path(), options);
      again->seek_to_record(records - 1);
      while (again->next(batch)) {
      }
    }
  } catch (const base::FormatError&) {
  } catch (const base::IoError&) {
  }
}

}  // namespace nodetrace::fuzz
