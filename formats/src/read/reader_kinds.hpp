// The reader of each input kind (internal), chosen by TraceReader::open
// (reader.cpp) from the input's first and last bytes (FORMAT.md section 3).
#pragma once

#include <memory>
#include <string>

#include "read/pipelined_reader.hpp"

namespace nodetrace::formats::detail {

// The container of FORMAT.md section 2 (its header magic is at the input's start).
std::unique_ptr<TraceReader> open_container_reader(OpenedInput opened, const ReaderOptions& options);
// A zstd stream from any tool (no header, no trailer), decompressed and read
// as plain records; `first_bytes` are its first 4 bytes.
std::unique_ptr<TraceReader> open_plain_zstd_reader(OpenedInput opened, const ReaderOptions& options,
                                                    std::string first_bytes);
// Plain din / extended din text or Dinero binary records.
std::unique_ptr<TraceReader> open_plain_records_reader(OpenedInput opened, const ReaderOptions& options);

}  // namespace nodetrace::formats::detail
