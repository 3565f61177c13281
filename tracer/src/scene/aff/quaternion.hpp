// Unit quaternions for the rotations of BART AFF keyframes: axis-angle
// keys, slerp, and the logarithm / exponential that Kochanek-Bartels tangents
// of rotations are taken in. Double precision; inline, internal to the AFF
// loader.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include "nodetrace/base/portable_math.hpp"

namespace nodetrace::tracer::detail::aff {

// The same results on every machine (portable_math.hpp).
namespace math = base::portable_math;

struct Quat {
  double w = 1, x = 0, y = 0, z = 0;
};

inline Quat operator*(const Quat& a, const Quat& b) {
  return {a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z, a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
          a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x, a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w};
}
inline Quat conjugate(const Quat& q) { return {q.w, -q.x, -q.y, -q.z}; }
inline double dot(const Quat& a, const Quat& b) { return a.w * b.w + a.x * b.x + a.y * b.y + a.z * b.z; }

inline Quat from_axis_angle(double ax, double ay, double az, double degrees) {
  const double len = std::sqrt(ax * ax + ay * ay + az * az);
  if (!(len > 0)) return {};
  const double half = degrees * std::numbers::pi / 360.0;
  const double s = math::sin(half) / len;
  return {math::cos(half), ax * s, ay * s, az * s};
}

// Logarithm of a unit quaternion: the rotation axis times half the angle.
inline std::array<double, 3> quat_log(const Quat& q) {
  const double v = std::sqrt(q.x * q.x + q.y * q.y + q.z * q.z);
  if (v < 1e-12) return {0, 0, 0};
  const double angle = math::atan2(v, q.w);
  return {q.x / v * angle, q.y / v * angle, q.z / v * angle};
}

inline Quat quat_exp(const std::array<double, 3>& a) {
  const double angle = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
  if (angle < 1e-12) return {};
  const double s = math::sin(angle) / angle;
  return {math::cos(angle), a[0] * s, a[1] * s, a[2] * s};
}

inline Quat slerp(const Quat& a, const Quat& b, double u) {
  const double cosine = std::clamp(dot(a, b), -1.0, 1.0);
  double wa = 1 - u, wb = u;
  const double theta = math::acos(cosine);
  if (math::sin(theta) > 1e-9) {
    wa = math::sin((1 - u) * theta) / math::sin(theta);
    wb = math::sin(u * theta) / math::sin(theta);
  }
  Quat r{wa * a.w + wb * b.w, wa * a.x + wb * b.x, wa * a.y + wb * b.y, wa * a.z + wb * b.z};
  const double n = std::sqrt(dot(r, r));
  return {r.w / n, r.x / n, r.y / n, r.z / n};
}

}  // namespace nodetrace::tracer::detail::aff
