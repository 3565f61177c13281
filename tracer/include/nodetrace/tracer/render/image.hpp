// A rendered picture and its outputs: a PNG for people, PFM float images for
// analysis tools.
#pragma once

#include <string>
#include <vector>

#include "nodetrace/tracer/geometry/vec3.hpp"

namespace nodetrace::tracer {

struct Image {
  int width = 0, height = 0;
  std::vector<Vec3> pixels;  // RGB, row-major from the top row (path tracing: the mean radiance)
  // Path tracing: each pixel's sample variance (unbiased, per channel, 0
  // with one sample), parallel to `pixels`; empty otherwise.
  std::vector<Vec3> variance;
  // Path tracing: pixels are linear radiance, shown through the sRGB curve.
  bool linear_radiance = false;
};

// 8-bit RGB PNG written to a temporary name and renamed into place. Values
// are clamped to 0..1; linear radiance then goes through the sRGB transfer
// curve (IEC 61966-2-1), Whitted colours are written as they are. Throws
// base::IoError when the file cannot be written.
void write_png(const Image& image, const std::string& path);

// A colour PFM ("PF", little-endian 32-bit floats, bottom row first, as the
// format has it) of `plane` (image.pixels or image.variance), written the same way.
void write_pfm(const Image& image, const std::vector<Vec3>& plane, const std::string& path);

}  // namespace nodetrace::tracer
