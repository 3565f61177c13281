// What traversals of every tree do with boxes: the ray/box slab test and a
// box's surface area. Internal header.
#pragma once

#include <limits>
#include <utility>

#include "nodetrace/tracer/scene/scene.hpp"

namespace nodetrace::tracer::detail {

// Slab test with the conservative rounding of Ize (2013) so a ray grazing a
// box is not lost. On entry t1 is the farthest distance wanted; on a hit
// [t0, t1] is the part of the ray inside the box (t0 >= 0).
inline bool intersect_box(const Bounds& box, const Vec3& origin, const Vec3& inverse, float& t0, float& t1) {
  constexpr float kGrow = 1.0f + 2.0f * 3.0f * std::numeric_limits<float>::epsilon();
  t0 = 0.0f;
  for (int axis = 0; axis < 3; ++axis) {
    float near = (box.lo[axis] - origin[axis]) * inverse[axis];
    float far = (box.hi[axis] - origin[axis]) * inverse[axis];
    if (near > far) std::swap(near, far);
    far *= kGrow;
    // NaN (0 * inf) leaves the bound as it was.
    t0 = near > t0 ? near : t0;
    t1 = far < t1 ? far : t1;
    if (t0 > t1) return false;
  }
  return true;
}

// Surface area (0 for an empty box), in double so large scenes do not overflow.
inline double box_area(const Bounds& box) {
  if (box.empty()) return 0.0;
  const double x = double(box.hi.x) - box.lo.x, y = double(box.hi.y) - box.lo.y, z = double(box.hi.z) - box.lo.z;
  return 2.0 * (x * y + y * z + z * x);
}

}  // namespace nodetrace::tracer::detail
