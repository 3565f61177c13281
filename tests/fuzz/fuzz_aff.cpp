// BART AFF scenes (includes resolve inside the fuzzing folder).
#include "fuzz_scene.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  nodetrace::fuzz::put_file("scene.aff", nodetrace::fuzz::as_text(data, size));
  nodetrace::fuzz::load_scene("scene.aff");
  return 0;
}
