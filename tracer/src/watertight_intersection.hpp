// The watertight ray/triangle test (Woop, Benthin and Wald 2013), inline for
// the traversal loop. Internal header: the public entry is
// intersect_triangle (render.hpp).
//
// Edge functions are computed in double from the sheared float coordinates:
// a product of two floats is exact in double, so each edge function has the
// exact sign, and two triangles sharing an edge see exactly opposite values.
// A ray exactly on an edge or vertex is given to one triangle by a tie rule
// (a consistent symbolic perturbation of the ray, as rasterisers' top-left
// rule), so it hits a shared edge, or the shared vertex of a closed fan,
// exactly once. Hits closer than the rounding error of t (the bound of PBR
// 4th ed., section 6.8.4) are rejected, so a ray never finds a triangle it
// starts on. Every step is exact under scaling by a power of two.
#pragma once

#include <algorithm>
#include <cmath>
#include <utility>

#include "nodetrace/tracer/interaction.hpp"
#include "nodetrace/tracer/render.hpp"

namespace nodetrace::tracer::detail {

// The per-ray part of the test: the axis the ray runs along most (kz) and
// the shear that turns the ray into the +z axis.
struct ShearedRay {
  Vec3 origin;
  int kx, ky, kz;
  float sx, sy, sz;
  explicit ShearedRay(const Ray& ray) : origin(ray.origin) {
    const Vec3& d = ray.direction;
    const Vec3 ad{std::fabs(d.x), std::fabs(d.y), std::fabs(d.z)};
    kz = ad.x > ad.y ? (ad.x > ad.z ? 0 : 2) : (ad.y > ad.z ? 1 : 2);
    kx = (kz + 1) % 3;
    ky = (kx + 1) % 3;
    if (d[kz] < 0) std::swap(kx, ky);  // keep the winding
    sx = d[kx] / d[kz];
    sy = d[ky] / d[kz];
    sz = 1.0f / d[kz];
  }
};

// Whether a triangle owns the part of its boundary on the 2-D edge vector
// (ex, ey), oriented with the triangle on its left: the ray is taken as moved
// by (-e, e^2) for an infinitesimal e, so of two triangles on either side of
// an edge exactly one owns it, and of a closed fan exactly one its centre.
inline bool owns_edge(float ex, float ey) { return ey > 0 || (ey == 0 && ex > 0); }

inline bool intersect_sheared(const ShearedRay& r, const Triangle& triangle, float t_max, Hit& hit) {
  const Vec3 a = triangle.v0 - r.origin, b = triangle.v1 - r.origin, c = triangle.v2 - r.origin;
  const float ax = a[r.kx] - r.sx * a[r.kz], ay = a[r.ky] - r.sy * a[r.kz];
  const float bx = b[r.kx] - r.sx * b[r.kz], by = b[r.ky] - r.sy * b[r.kz];
  const float cx = c[r.kx] - r.sx * c[r.kz], cy = c[r.ky] - r.sy * c[r.kz];
  // e0 weighs v0 (edge v1-v2), e1 weighs v1, e2 weighs v2.
  const double e0 = double(cx) * by - double(cy) * bx;
  const double e1 = double(ax) * cy - double(ay) * cx;
  const double e2 = double(bx) * ay - double(by) * ax;
  if ((e0 < 0 || e1 < 0 || e2 < 0) && (e0 > 0 || e1 > 0 || e2 > 0)) return false;
  const double det = e0 + e1 + e2;
  if (det == 0) return false;
  if (e0 == 0 || e1 == 0 || e2 == 0) {
    const float s = det > 0 ? 1.0f : -1.0f;
    if (e0 == 0 && !owns_edge(s * (bx - cx), s * (by - cy))) return false;
    if (e1 == 0 && !owns_edge(s * (cx - ax), s * (cy - ay))) return false;
    if (e2 == 0 && !owns_edge(s * (ax - bx), s * (ay - by))) return false;
  }
  const float az = r.sz * a[r.kz], bz = r.sz * b[r.kz], cz = r.sz * c[r.kz];
  const double t_scaled = e0 * az + e1 * bz + e2 * cz;
  const double t_limit = double(t_max) * det;
  if (det > 0 ? (t_scaled <= 0 || t_scaled >= t_limit) : (t_scaled >= 0 || t_scaled <= t_limit)) {
    return false;
  }
  const double inverse = 1.0 / det;
  const double t = t_scaled * inverse;
  // Reject t within its own rounding error (bounds for the float version of
  // this computation, which bound the more exact one here as well). PBR
  // adds the scaled z to x and y; the sheared x and y are made from the
  // unscaled z (distances), and using those keeps the bound homogeneous
  // for a direction of any length.
  const double max_x = std::max({std::fabs(ax), std::fabs(bx), std::fabs(cx)});
  const double max_y = std::max({std::fabs(ay), std::fabs(by), std::fabs(cy)});
  const double max_z = std::max({std::fabs(az), std::fabs(bz), std::fabs(cz)});
  const double max_distance_z = std::max({std::fabs(a[r.kz]), std::fabs(b[r.kz]), std::fabs(c[r.kz])});
  const double max_e = std::max({std::fabs(e0), std::fabs(e1), std::fabs(e2)});
  const double delta_z = error_gamma(3) * max_z;
  const double delta_x = error_gamma(5) * (max_x + max_distance_z);
  const double delta_y = error_gamma(5) * (max_y + max_distance_z);
  const double delta_e = 2 * (error_gamma(2) * max_x * max_y + delta_y * max_x + delta_x * max_y);
  const double delta_t =
      3 * (error_gamma(3) * max_e * max_z + delta_e * max_z + delta_z * max_e) * std::fabs(inverse);
  if (t <= delta_t) return false;
  hit.t = static_cast<float>(t);
  hit.b0 = static_cast<float>(e0 * inverse);
  hit.u = static_cast<float>(e1 * inverse);
  hit.v = static_cast<float>(e2 * inverse);
  return true;
}

}  // namespace nodetrace::tracer::detail
