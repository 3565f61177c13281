#include "nodetrace/tracer/render/interaction.hpp"

#include <algorithm>
#include <cmath>

namespace nodetrace::tracer {

namespace {

Vec3 abs(const Vec3& v) { return {std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)}; }
float max_abs_component(const Vec3& v) { return std::max({std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)}); }

// 2^-e for the exponent e of `magnitude` (> 0), so magnitude * it is in [1, 2).
float power_of_two_scale(float magnitude) { return std::ldexp(1.0f, -std::ilogb(magnitude)); }

}  // namespace

SurfacePoint interpolate_surface_point(const Triangle& triangle, float b0, float b1, float b2) {
  SurfacePoint result;
  result.point = triangle.v0 * b0 + triangle.v1 * b1 + triangle.v2 * b2;
  const Vec3 magnitude = abs(triangle.v0 * b0) + abs(triangle.v1 * b1) + abs(triangle.v2 * b2);
  result.error = magnitude * error_gamma(7);
  return result;
}

Vec3 offset_ray_origin(const SurfacePoint& point, const Vec3& normal) {
  const float distance = dot(abs(normal), point.error);
  const Vec3 offset = normal * distance;
  Vec3 origin = point.point + offset;
  constexpr float kInf = std::numeric_limits<float>::infinity();
  for (int axis = 0; axis < 3; ++axis) {
    // Rounding of the sum may have pulled the origin back into the box.
    if (offset[axis] > 0) {
      origin[axis] = std::nextafter(origin[axis], kInf);
    } else if (offset[axis] < 0) {
      origin[axis] = std::nextafter(origin[axis], -kInf);
    }
  }
  return origin;
}

Vec3 unit_vector(const Vec3& v) {
  const float largest = max_abs_component(v);
  if (!(largest > 0) || !std::isfinite(largest)) return largest > 0 ? v : Vec3{};
  const Vec3 scaled = v * power_of_two_scale(largest);
  return scaled / length(scaled);
}

Vec3 triangle_unit_normal(const Triangle& triangle, const Vec3& fallback) {
  Vec3 e1 = triangle.v1 - triangle.v0, e2 = triangle.v2 - triangle.v0;
  const float largest = std::max(max_abs_component(e1), max_abs_component(e2));
  if (!(largest > 0)) return fallback;
  const float scale = power_of_two_scale(largest);
  e1 *= scale;
  e2 *= scale;
  const Vec3 n = cross(e1, e2);
  if (!(max_abs_component(n) > 0)) return fallback;
  return unit_vector(n);
}

}  // namespace nodetrace::tracer
