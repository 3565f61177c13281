// The one mapping between world directions and the pixels of an
// equirectangular (latitude-longitude) map: Blender's, so a map lights a
// scene here as Blender's Environment Texture node (equirectangular
// projection, no rotation) lights the same triangles there, with no axis
// conversion. Blender's Cycles kernel (direction_to_equirectangular) and its
// GPU shader (node_tex_environment_equirectangular) both compute, for a
// direction d in a Z-up world,
//   u = 0.5 - atan2(d.y, d.x) / (2 pi)             (0..1, left to right)
//   v = 0.5 + atan2(d.z, hypot(d.x, d.y)) / pi     (0..1, bottom to top)
// so +X is the middle column (u = 0.5), +Y a quarter of the width from the
// left (u = 0.25), -Y three quarters (u = 0.75), -X the left and right edge
// (u = 0 = 1), +Z the top row and -Z the bottom row. The pixel is column
// floor(u W) (wrapped into 0..W-1) and row floor(v H) counted from the
// bottom (the top row for v = 1), as Cycles' "Closest" interpolation picks
// it; PFM files and Blender images both store the bottom row first.
#pragma once

#include <cstdint>

#include "nodetrace/tracer/geometry/vec3.hpp"

namespace nodetrace::tracer {

struct EquirectangularUv {
  double u = 0, v = 0;
};

// u and v of a nonzero direction (any length).
EquirectangularUv equirectangular_uv(const Vec3& direction);

// The unit direction at (u, v): the inverse of equirectangular_uv.
Vec3 equirectangular_direction(double u, double v);

struct MapPixel {
  std::uint32_t column = 0;
  std::uint32_t row = 0;  // from the top: 0 is +Z's row, as Image stores rows
};

// The pixel of a width x height map that `direction` looks up.
MapPixel equirectangular_pixel(const Vec3& direction, std::uint32_t width, std::uint32_t height);

}  // namespace nodetrace::tracer
