#include "scene/triangle_checks.hpp"

#include <cmath>
#include <cstdio>

#include "nodetrace/tracer/scene/scene_loader.hpp"

namespace nodetrace::tracer::detail {

namespace {

std::string number(float value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.9g", double(value));
  return text;
}

}  // namespace

void check_coordinates_in_range(const Triangle& triangle, const std::function<std::string()>& where) {
  for (const Vec3* v : {&triangle.v0, &triangle.v1, &triangle.v2}) {
    for (int axis = 0; axis < 3; ++axis) {
      const float x = (*v)[axis];
      if (std::isnan(x)) throw SceneError(where() + ": triangle vertex coordinate is not a number");
      if (!(std::fabs(x) <= kMaxSceneCoordinate)) {
        throw SceneError(where() + ": triangle vertex coordinate " + number(x) +
                         " is beyond the supported range of -2^62 to 2^62 (about +-4.6e18)" +
                         (std::isinf(x) ? " (it overflows single precision)" : ""));
      }
    }
  }
}

bool TriangleChecks::keep(const Triangle& triangle, const std::function<std::string()>& where) {
  check_coordinates_in_range(triangle, where);
  // Zero area exactly: in double, so a tiny triangle (a 1e-30 sliver) whose
  // float cross product underflows is kept.
  const double ax = double(triangle.v1.x) - triangle.v0.x, ay = double(triangle.v1.y) - triangle.v0.y,
               az = double(triangle.v1.z) - triangle.v0.z;
  const double bx = double(triangle.v2.x) - triangle.v0.x, by = double(triangle.v2.y) - triangle.v0.y,
               bz = double(triangle.v2.z) - triangle.v0.z;
  const double nx = ay * bz - az * by, ny = az * bx - ax * bz, nz = ax * by - ay * bx;
  if (nx != 0 || ny != 0 || nz != 0) return true;
  if (dropped_++ == 0) first_dropped_ = where();
  return false;
}

std::optional<std::string> TriangleChecks::warning() const {
  if (dropped_ == 0) return std::nullopt;
  return std::to_string(dropped_) + (dropped_ == 1 ? " zero-area triangle" : " zero-area triangles") +
         " dropped (the first at " + first_dropped_ + ")";
}

}  // namespace nodetrace::tracer::detail
