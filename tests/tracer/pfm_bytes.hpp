// Colour PFM files' bytes for the environment map suites.
#pragma once

#include <cstdint>
#include <cstring>
#include <string>

#include "nodetrace/tracer/geometry/vec3.hpp"

namespace nodetrace::tracer::test_files {

// A colour PFM of `width` x `height` whose pixel (x, y from the top) is
// `colour(x, y)`, bottom row first, in either byte order.
template <typename Colour>
inline std::string pfm_bytes(int width, int height, Colour colour, bool little_endian = true) {
  std::string bytes = "PF\n" + std::to_string(width) + " " + std::to_string(height) + "\n" +
                      (little_endian ? "-1.0" : "1.0") + "\n";
  for (int stored = 0; stored < height; ++stored) {
    for (int x = 0; x < width; ++x) {
      const Vec3 c = colour(x, height - 1 - stored);
      for (int k = 0; k < 3; ++k) {
        std::uint32_t bits;
        const float value = c[k];
        std::memcpy(&bits, &value, 4);
        for (int b = 0; b < 4; ++b) bytes += char((bits >> (8 * (little_endian ? b : 3 - b))) & 0xFF);
      }
    }
  }
  return bytes;
}

}  // namespace nodetrace::tracer::test_files
