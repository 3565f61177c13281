// Affine transforms of the AFF scene graph (`xs` blocks, keyframed `x`
// blocks), in double precision; inline, internal to the AFF loader: the
// per-vertex point() runs for every triangle of every frame.
#pragma once

#include <array>

#include "scene/aff/quaternion.hpp"
#include "nodetrace/tracer/geometry/vec3.hpp"

namespace nodetrace::tracer::detail::aff {

// Affine transform in double precision: 3x3 linear part and translation.
struct Affine {
  std::array<std::array<double, 4>, 3> m{{{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}}};

  static Affine translation(double x, double y, double z) {
    Affine a;
    a.m[0][3] = x, a.m[1][3] = y, a.m[2][3] = z;
    return a;
  }
  static Affine scaling(double x, double y, double z) {
    Affine a;
    a.m[0][0] = x, a.m[1][1] = y, a.m[2][2] = z;
    return a;
  }
  static Affine rotation(const Quat& q) {
    Affine a;
    const double w = q.w, x = q.x, y = q.y, z = q.z;
    a.m[0] = {1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y), 0};
    a.m[1] = {2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x), 0};
    a.m[2] = {2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y), 0};
    return a;
  }
  Affine operator*(const Affine& o) const {
    Affine r;
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 4; ++j) {
        r.m[i][j] = m[i][0] * o.m[0][j] + m[i][1] * o.m[1][j] + m[i][2] * o.m[2][j] + (j == 3 ? m[i][3] : 0);
      }
    }
    return r;
  }
  Vec3 point(const Vec3& p) const {
    return {static_cast<float>(m[0][0] * p.x + m[0][1] * p.y + m[0][2] * p.z + m[0][3]),
            static_cast<float>(m[1][0] * p.x + m[1][1] * p.y + m[1][2] * p.z + m[1][3]),
            static_cast<float>(m[2][0] * p.x + m[2][1] * p.y + m[2][2] * p.z + m[2][3])};
  }
  Vec3 direction(const Vec3& d) const {
    return {static_cast<float>(m[0][0] * d.x + m[0][1] * d.y + m[0][2] * d.z),
            static_cast<float>(m[1][0] * d.x + m[1][1] * d.y + m[1][2] * d.z),
            static_cast<float>(m[2][0] * d.x + m[2][1] * d.y + m[2][2] * d.z)};
  }
  // Inverse transpose of the linear part (for normals), up to scale.
  Affine normal_matrix() const {
    Affine r;
    // Cofactor matrix = det * inverse transpose; the scale is normalized away.
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) {
        const int i1 = (i + 1) % 3, i2 = (i + 2) % 3, j1 = (j + 1) % 3, j2 = (j + 2) % 3;
        r.m[i][j] = m[i1][j1] * m[i2][j2] - m[i1][j2] * m[i2][j1];
      }
      r.m[i][3] = 0;
    }
    return r;
  }
};

}  // namespace nodetrace::tracer::detail::aff
