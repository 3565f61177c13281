// A rendered picture and its PNG output.
#pragma once

#include <string>
#include <vector>

#include "nodetrace/tracer/geometry/vec3.hpp"

namespace nodetrace::tracer {

struct Image {
  int width = 0, height = 0;
  std::vector<Vec3> pixels;  // RGB, row-major from the top row
};

// 8-bit RGB PNG (values clamped to 0..1, no gamma curve) written to a temporary name and renamed into place. Throws
// base::IoError when the file cannot be written.
void write_png(const Image& image, const std::string& path);

}  // namespace nodetrace::tracer
