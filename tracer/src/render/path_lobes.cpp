#include "render/path_lobes.hpp"

#include <algorithm>
#include <cmath>

#include "nodetrace/base/portable_math.hpp"

namespace nodetrace::tracer::detail {

namespace math = base::portable_math;  // the same directions on every machine

namespace {

constexpr float kTwoPi = 6.28318530717958647692f;

float positive_or_zero(float value) { return value > 0 ? value : 0.0f; }
float mean(const Vec3& c) { return (c.x + c.y + c.z) / 3.0f; }

// `local` (z along n) in the world.
Vec3 around(const Vec3& n, const Vec3& local) { return Frame(n).to_world(local); }

Vec3 on_cone(const Vec3& axis, float cos_theta, float u) {
  const float sin_theta = std::sqrt(std::max(0.0f, 1.0f - cos_theta * cos_theta));
  const float phi = kTwoPi * u;
  return normalize(around(axis, {sin_theta * math::cos(phi), sin_theta * math::sin(phi), cos_theta}));
}

}  // namespace

// The branchless orthonormal basis of Duff et al., "Building an Orthonormal
// Basis, Revisited" (JCGT 2017).
Frame::Frame(const Vec3& n) : normal(n) {
  const float sign = std::copysign(1.0f, n.z);
  const float a = -1.0f / (sign + n.z);
  const float b = n.x * n.y * a;
  tangent = {1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x};
  bitangent = {b, sign + n.y * n.y * a, -n.y};
}

LobeWeights lobe_weights(const Material& material) {
  LobeWeights w;
  w.diffuse = positive_or_zero(mean(material.diffuse));
  w.glossy = material.shininess > 0 ? positive_or_zero(mean(material.specular)) : 0.0f;
  w.mirror = positive_or_zero(material.reflectance);
  w.dielectric = positive_or_zero(material.transmittance);
  w.ggx = material.ggx_roughness > 0 ? positive_or_zero(mean(material.ggx_color)) : 0.0f;
  return w;
}

Vec3 sample_cosine(const Vec3& n, float u1, float u2) { return on_cone(n, std::sqrt(1.0f - u1), u2); }

Vec3 sample_phong(const Vec3& axis, float exponent, float u1, float u2) {
  // 1 - u1 is in (0, 1]: pow never sees 0 to a tiny power.
  return on_cone(axis, math::pow(1.0f - u1, 1.0f / (exponent + 1.0f)), u2);
}

}  // namespace nodetrace::tracer::detail
