// The watertight ray/triangle test (Woop, Benthin and Wald 2013), inline for
// the traversal loop. Internal header: the public entry is
// intersect_triangle (ray.hpp).
//
// Everything after the float inputs is computed in double: translation,
// shear and edge functions, each vertex on its own, so two triangles sharing
// an edge see exactly opposite edge values (watertight), and the rounding
// error is some 1e-16 of the magnitudes, far below float's.
// A ray exactly on an edge or vertex is given to one triangle by a tie rule
// (a consistent symbolic perturbation of the ray, as rasterisers' top-left
// rule), so it hits a shared edge, or the shared vertex of a closed fan,
// exactly once. Hits closer than the rounding error of t (the bound of PBR
// 4th ed., section 6.8.4) are rejected, so a ray never finds a triangle it
// starts on. Every step is exact under scaling by a power of two.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <utility>

#include "nodetrace/tracer/render/interaction.hpp"
#include "nodetrace/tracer/geometry/ray.hpp"

namespace nodetrace::tracer::detail {

// Higham's gamma(n) in double precision.
constexpr double error_gamma_double(int n) {
  constexpr double half_eps = std::numeric_limits<double>::epsilon() * 0.5;
  return (double(n) * half_eps) / (1.0 - double(n) * half_eps);
}

// The per-ray part of the test: the axis the ray runs along most (kz) and
// the shear that turns the ray into the +z axis, in double.
struct ShearedRay {
  double ox, oy, oz;  // origin on the kx, ky, kz axes
  int kx, ky, kz;
  double sx, sy, sz;
  // Without branches: the axes differ from ray to ray, so each branch
  // choosing them was a likely misprediction on every ray.
  explicit ShearedRay(const Ray& ray) {
    float d[3], o[3];
    std::memcpy(d, &ray.direction, sizeof d);
    std::memcpy(o, &ray.origin, sizeof o);
    const bool x_over_y = std::fabs(d[0]) > std::fabs(d[1]);
    const bool x_over_z = std::fabs(d[0]) > std::fabs(d[2]);
    const bool y_over_z = std::fabs(d[1]) > std::fabs(d[2]);
    // x_over_y ? (x_over_z ? 0 : 2) : (y_over_z ? 1 : 2)
    kz = 2 - 2 * int(x_over_y & x_over_z) - int(!x_over_y & y_over_z);
    // (kz + 1) % 3 and (kz + 2) % 3 as 2-bit tables {1, 2, 0} and {2, 0, 1}.
    const int after_kz = (0x9 >> (2 * kz)) & 3, after_that = (0x12 >> (2 * kz)) & 3;
    const int keep_winding = -int(d[kz] < 0);  // all ones: swap kx and ky
    kx = after_kz ^ ((after_kz ^ after_that) & keep_winding);
    ky = after_that ^ ((after_kz ^ after_that) & keep_winding);
    sx = double(d[kx]) / d[kz];
    sy = double(d[ky]) / d[kz];
    sz = 1.0 / d[kz];
    ox = o[kx], oy = o[ky], oz = o[kz];
  }
};

// Whether a triangle owns the part of its boundary on the 2-D edge vector
// (ex, ey), oriented with the triangle on its left: the ray is taken as moved
// by (-e, e^2) for an infinitesimal e, so of two triangles on either side of
// an edge exactly one owns it, and of a closed fan exactly one its centre.
inline bool owns_edge(double ex, double ey) { return ey > 0 || (ey == 0 && ex > 0); }

inline bool intersect_sheared(const ShearedRay& r, const Triangle& triangle, float t_max, Hit& hit) {
  // Vertices relative to the origin, sheared: each vertex is transformed on
  // its own, so a vertex shared by two triangles gives both the same bits.
  struct Sheared {
    double x, y, z, distance_z;
  };
  // Coordinates read by index from the vertex's bytes: Vec3's operator[]
  // branches on the axis, and the axes change from ray to ray.
  auto shear = [&r](const Vec3& vertex) {
    static_assert(sizeof(Vec3) == 3 * sizeof(float));
    float v[3];
    std::memcpy(v, &vertex, sizeof v);
    const double z = v[r.kz] - r.oz;
    return Sheared{(v[r.kx] - r.ox) - r.sx * z, (v[r.ky] - r.oy) - r.sy * z, r.sz * z, z};
  };
  const Sheared a = shear(triangle.v0), b = shear(triangle.v1), c = shear(triangle.v2);
  // e0 weighs v0 (edge v1-v2), e1 weighs v1, e2 weighs v2. Written so that
  // the triangle across an edge computes exactly the negated value.
  const double e0 = c.x * b.y - c.y * b.x;
  const double e1 = a.x * c.y - a.y * c.x;
  const double e2 = b.x * a.y - b.y * a.x;
  // One branch on the combined signs: whether a ray misses is data, badly
  // predicted, and a chain of short-circuit branches mispredicts once per
  // link (| evaluates every compare without a branch; the shift keeps GCC
  // from splitting `neg & pos` back into two branches).
  const bool some_negative = (e0 < 0) | (e1 < 0) | (e2 < 0);
  const bool some_positive = (e0 > 0) | (e1 > 0) | (e2 > 0);
  if ((unsigned{some_negative} << 1 | unsigned{some_positive}) == 3u) return false;
  const double det = e0 + e1 + e2;
  if (det == 0) return false;
  if (e0 == 0 || e1 == 0 || e2 == 0) {
    const double s = det > 0 ? 1.0 : -1.0;
    if (e0 == 0 && !owns_edge(s * (b.x - c.x), s * (b.y - c.y))) return false;
    if (e1 == 0 && !owns_edge(s * (c.x - a.x), s * (c.y - a.y))) return false;
    if (e2 == 0 && !owns_edge(s * (a.x - b.x), s * (a.y - b.y))) return false;
  }
  const double t_scaled = e0 * a.z + e1 * b.z + e2 * c.z;
  const double t_limit = double(t_max) * det;
  // One branch, as above, on whether t lies outside (0, t_max).
  const bool positive = det > 0;
  const bool outside_positive = (t_scaled <= 0) | (t_scaled >= t_limit);
  const bool outside_negative = (t_scaled >= 0) | (t_scaled <= t_limit);
  if ((positive & outside_positive) | (!positive & outside_negative)) return false;
  const double inverse = 1.0 / det;
  const double t = t_scaled * inverse;
  // Reject t within its own rounding error: the bound of PBR 4th ed.,
  // section 6.8.4, for this computation in double. PBR adds max |z| to the
  // x and y terms; the shear's error comes from |sx z| (|sx| <= 1), which
  // keeps the bound homogeneous for a direction of any length and far
  // tighter for big triangles seen at small angles.
  const double max_x = std::max({std::fabs(a.x), std::fabs(b.x), std::fabs(c.x)});
  const double max_y = std::max({std::fabs(a.y), std::fabs(b.y), std::fabs(c.y)});
  const double max_z = std::max({std::fabs(a.z), std::fabs(b.z), std::fabs(c.z)});
  const double max_dz = std::max({std::fabs(a.distance_z), std::fabs(b.distance_z), std::fabs(c.distance_z)});
  const double max_e = std::max({std::fabs(e0), std::fabs(e1), std::fabs(e2)});
  const double delta_z = error_gamma_double(3) * max_z;
  const double delta_x = error_gamma_double(5) * (max_x + 2 * std::fabs(r.sx) * max_dz);
  const double delta_y = error_gamma_double(5) * (max_y + 2 * std::fabs(r.sy) * max_dz);
  const double delta_e = 2 * (error_gamma_double(2) * max_x * max_y + delta_y * max_x + delta_x * max_y);
  const double delta_t =
      3 * (error_gamma_double(3) * max_e * max_z + delta_e * max_z + delta_z * max_e) * std::fabs(inverse);
  if (t <= delta_t) return false;
  hit.t = static_cast<float>(t);
  hit.b0 = static_cast<float>(e0 * inverse);
  hit.u = static_cast<float>(e1 * inverse);
  hit.v = static_cast<float>(e2 * inverse);
  return true;
}

}  // namespace nodetrace::tracer::detail
