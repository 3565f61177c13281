// Where a ray hit a triangle, how far off that point may be, and where a new
// ray may start from it: the hit point is interpolated from barycentrics and
// carries a conservative bound on its rounding error (Pharr, Jakob and
// Humphreys, "Physically Based Rendering", 4th ed., section 6.8, with the
// gamma(n) = n eps / (1 - n eps) factors of Higham's analysis). A spawned ray
// starts just outside that error box along the geometric normal, so it can
// neither re-hit the surface it leaves nor slip through a closed mesh, at
// any scale: every step is exact under scaling by a power of two.
#pragma once

#include <limits>

#include "nodetrace/tracer/scene/scene.hpp"
#include "nodetrace/tracer/geometry/vec3.hpp"

namespace nodetrace::tracer {

// Higham's gamma(n): bounds the relative error of n floating-point operations.
constexpr float error_gamma(int n) {
  constexpr float half_eps = std::numeric_limits<float>::epsilon() * 0.5f;
  return (float(n) * half_eps) / (1.0f - float(n) * half_eps);
}

// A hit point and the bound on its error per axis (|exact - point| <= error).
struct SurfacePoint {
  Vec3 point;
  Vec3 error;
};

// The point at barycentrics (b0, b1, b2) of v0, v1, v2; the error bound holds
// for barycentrics computed as the intersection test computes them.
SurfacePoint interpolate_surface_point(const Triangle& triangle, float b0, float b1, float b2);

// `point` moved past its error box along `normal` (the unit normal of the
// side the new ray leaves towards), then one float further on each axis.
Vec3 offset_ray_origin(const SurfacePoint& point, const Vec3& normal);

// v / |v|, computed after an exact power-of-two rescaling so that |v|^2
// neither overflows nor underflows; bit-identical to v / |v| whenever that
// does neither. The zero vector gives zero.
Vec3 unit_vector(const Vec3& v);

// The unit geometric normal (v1 - v0) x (v2 - v0) / |...|, exact under
// scaling; `fallback` for a zero-area triangle.
Vec3 triangle_unit_normal(const Triangle& triangle, const Vec3& fallback);

}  // namespace nodetrace::tracer
