// Wavefront OBJ with its MTL: the bytes before the first NUL are scene.obj,
// the rest scene.mtl (seeds say `mtllib scene.mtl`).
#include "fuzz_scene.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view bytes = nodetrace::fuzz::as_text(data, size);
  const std::size_t split = std::min(bytes.find('\0'), bytes.size());
  nodetrace::fuzz::put_file("scene.obj", bytes.substr(0, split));
  nodetrace::fuzz::put_file("scene.mtl", split < bytes.size() ? bytes.substr(split + 1) : std::string_view());
  nodetrace::fuzz::load_scene("scene.obj");
  return 0;
}
