// Whatever the reader detects: the container (header, markers, data frames,
// trailer, footer), plain zstd streams, plain text.
#include "fuzz_reader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  nodetrace::fuzz::read_trace(nodetrace::fuzz::as_text(data, size), std::nullopt, false);
  return 0;
}
