#include "render/ggx.hpp"

#include <algorithm>
#include <cmath>

#include "nodetrace/base/portable_math.hpp"

namespace nodetrace::tracer::detail {

namespace math = base::portable_math;  // the same directions on every machine

namespace {

constexpr float kPi = 3.14159265358979323846f;
constexpr float kTwoPi = 6.28318530717958647692f;

// G1 from cos theta (above 0) and alpha^2.
float smith_g1(float cos_theta, float alpha2) {
  const float cos2 = cos_theta * cos_theta;
  const float tan2 = std::max(0.0f, 1.0f - cos2) / cos2;
  return 2.0f / (1.0f + std::sqrt(1.0f + alpha2 * tan2));
}

}  // namespace

float ggx_alpha(float roughness) { return std::max(roughness * roughness, kMinGgxAlpha); }

GgxLobe::GgxLobe(float alpha, const Vec3& normal, const Vec3& view)
    : alpha_(alpha), alpha2_(alpha * alpha), frame_(normal), view_(view), cos_view_(dot(normal, view)),
      masking_view_(cos_view_ > 0 ? smith_g1(cos_view_, alpha2_) : 0.0f) {}

float GgxLobe::distribution(const Vec3& half) const {
  const float cos_h = dot(frame_.normal, half);
  if (!(cos_h > 0)) return 0;
  // 1 + (alpha^2 - 1) cos^2 as alpha^2 cos^2 + sin^2, with sin^2 from the
  // cross product: exact where a narrow lobe peaks (cos near 1).
  const Vec3 across = cross(frame_.normal, half);
  const float t = alpha2_ * cos_h * cos_h + dot(across, across);
  return alpha2_ / (kPi * t * t);
}

float GgxLobe::masking(const Vec3& direction) const {
  const float cos_theta = dot(frame_.normal, direction);
  return cos_theta > 0 ? smith_g1(cos_theta, alpha2_) : 0.0f;
}

float GgxLobe::brdf_cos(const Vec3& light) const {
  if (!(cos_view_ > 0) || !(dot(frame_.normal, light) > 0)) return 0;
  const Vec3 half = normalize(view_ + light);
  return distribution(half) * masking_view_ * masking(light) / (4.0f * cos_view_);
}

float GgxLobe::point_light(const Vec3& light) const { return kPi * brdf_cos(light); }

float GgxLobe::pdf(const Vec3& light) const {
  if (!(cos_view_ > 0)) return 0;
  const Vec3 sum = view_ + light;
  if (!(dot(sum, sum) > 0)) return 0;
  return masking_view_ * distribution(normalize(sum)) / (4.0f * cos_view_);
}

Vec3 GgxLobe::sample(float u1, float u2) const {
  // The view stretched to the hemisphere configuration (alpha 1).
  const Vec3 v = frame_.to_local(view_);
  const Vec3 stretched = normalize(Vec3{alpha_ * v.x, alpha_ * v.y, v.z});
  // A point uniform on the disk across it, its half beyond the view's
  // horizon squeezed towards the visible side (Heitz 2018, listing 1).
  const float length2 = stretched.x * stretched.x + stretched.y * stretched.y;
  const Vec3 t1 = length2 > 0 ? Vec3{-stretched.y, stretched.x, 0} / std::sqrt(length2) : Vec3{1, 0, 0};
  const Vec3 t2 = cross(stretched, t1);
  const float r = std::sqrt(u1);
  const float phi = kTwoPi * u2;
  const float p1 = r * math::cos(phi);
  const float s = 0.5f * (1.0f + stretched.z);
  const float p2 = (1.0f - s) * std::sqrt(std::max(0.0f, 1.0f - p1 * p1)) + s * (r * math::sin(phi));
  const Vec3 on_hemisphere =
      t1 * p1 + t2 * p2 + stretched * std::sqrt(std::max(0.0f, 1.0f - p1 * p1 - p2 * p2));
  // Unstretched: the microfacet normal, then the view reflected about it.
  const Vec3 m = normalize(Vec3{alpha_ * on_hemisphere.x, alpha_ * on_hemisphere.y,
                                std::max(0.0f, on_hemisphere.z)});
  const Vec3 reflected = m * (2.0f * dot(v, m)) - v;
  return normalize(frame_.to_world(reflected));
}

}  // namespace nodetrace::tracer::detail
