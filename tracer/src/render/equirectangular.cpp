#include "nodetrace/tracer/render/equirectangular.hpp"

#include <algorithm>
#include <cmath>

#include "nodetrace/base/portable_math.hpp"

namespace nodetrace::tracer {

namespace math = base::portable_math;  // the same pixel on every machine

namespace {
constexpr double kPi = 3.14159265358979323846;
}  // namespace

EquirectangularUv equirectangular_uv(const Vec3& direction) {
  const double x = direction.x, y = direction.y, z = direction.z;
  return {0.5 - math::atan2(y, x) / (2 * kPi), 0.5 + math::atan2(z, std::sqrt(x * x + y * y)) / kPi};
}

Vec3 equirectangular_direction(double u, double v) {
  const double phi = kPi * (1 - 2 * u), elevation = kPi * (v - 0.5);
  const double horizontal = math::cos(elevation);
  return {static_cast<float>(horizontal * math::cos(phi)), static_cast<float>(horizontal * math::sin(phi)),
          static_cast<float>(math::sin(elevation))};
}

MapPixel equirectangular_pixel(const Vec3& direction, std::uint32_t width, std::uint32_t height) {
  const EquirectangularUv uv = equirectangular_uv(direction);
  // u is in [0, 1]: u = 1 (-X from below the seam) wraps to column 0.
  const auto column = static_cast<std::uint32_t>(std::floor(uv.u * width)) % width;
  // v = 1 (straight up) is the top row, not one past it.
  const auto from_bottom = std::min(static_cast<std::uint32_t>(std::floor(uv.v * height)), height - 1);
  return {column, height - 1 - from_bottom};
}

}  // namespace nodetrace::tracer
