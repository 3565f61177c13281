// Extended din text (Dinero IV -informat D). The first byte chooses
// --tags-are-levels.
#include "fuzz_reader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  nodetrace::fuzz::read_trace(nodetrace::fuzz::as_text(data + 1, size - 1),
                              nodetrace::formats::RecordForm::ExtendedDin, (data[0] & 1) != 0);
  return 0;
}
