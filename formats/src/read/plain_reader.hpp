// What the two plain input kinds share (internal): they have no header and
// no trailer, and their bytes (raw, or decompressed from a zstd stream) are
// cut at record boundaries into chunks parsed on the workers.
#pragma once

#include <string>

#include "read/pipelined_reader.hpp"

namespace nodetrace::formats::detail {

// Bytes parsed per job: small enough that the few jobs in flight hold a few
// megabytes of text and records, large enough that hand-overs are rare.
inline constexpr std::size_t kPlainChunkBytes = 512u << 10;

class PlainReader : public PipelinedReader {
 public:
  using PipelinedReader::PipelinedReader;

 protected:
  // Appends the next run of record bytes to `out` (bytes kept from the run
  // before lead it: one copy of the text, not two); false, appending
  // nothing, at the end of the input.
  virtual bool append_plain_bytes(std::string& out) = 0;

  std::string first_plain_;  // bytes read ahead to detect the record form

 private:
  void read_decode_unit() final;

  std::string carry_;  // the bytes after the last whole record, waiting for more
};

}  // namespace nodetrace::formats::detail
