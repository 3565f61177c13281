// Dinero binary records (-informat b), plain or in a container.
#include "fuzz_reader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  nodetrace::fuzz::read_trace(nodetrace::fuzz::as_text(data, size), nodetrace::formats::RecordForm::Binary, false);
  return 0;
}
