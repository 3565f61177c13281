// A rendered picture and its outputs: a PNG for people, PFM float images for
// analysis tools; and the PFM reader (environment maps).
#pragma once

#include <cstdint>
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

// A colour PFM file: "PF", the width and height, the scale (negative:
// little-endian floats, positive: big-endian; its magnitude is ignored, as
// netpbm's pfmtopam ignores it), one whitespace character, then exactly
// width x height x 3 floats, bottom row first. Returns the pixels top row
// first (Image's order). Throws base::IoError when the file cannot be read
// and base::FormatError, naming the file, for anything else: not a PFM, a
// greyscale one ("Pf"), a size of 0 or above `max_pixels`, too few or too
// many bytes. The values are returned as stored (NaN included).
Image read_pfm(const std::string& path, std::uint64_t max_pixels);

}  // namespace nodetrace::tracer
