// Mirror reflection and the Fresnel split of light at a dielectric boundary
// (Snell's law, total internal reflection). Internal header of the shader.
#pragma once

#include <algorithm>
#include <cmath>

#include "nodetrace/tracer/geometry/vec3.hpp"

namespace nodetrace::tracer::detail {

inline Vec3 reflect(const Vec3& d, const Vec3& n) { return d - n * (2.0f * dot(d, n)); }

// Unpolarised Fresnel reflectance of a dielectric; cos_i and cos_t positive.
inline float fresnel_dielectric(float cos_i, float cos_t, float eta_i, float eta_t) {
  const float parallel = (eta_t * cos_i - eta_i * cos_t) / (eta_t * cos_i + eta_i * cos_t);
  const float perpendicular = (eta_i * cos_i - eta_t * cos_t) / (eta_i * cos_i + eta_t * cos_t);
  return 0.5f * (parallel * parallel + perpendicular * perpendicular);
}

// Light arriving along -view at a boundary with unit normal `normal` (on the
// side of view), from index eta_i into eta_t.
struct Refraction {
  bool total_internal = false;  // nothing is transmitted
  float reflectance = 1;        // Fresnel: the reflected share
  Vec3 direction;               // of the transmitted ray, unless total_internal
};

inline Refraction refract(const Vec3& view, const Vec3& normal, float eta_i, float eta_t) {
  Refraction result;
  const float cos_i = std::clamp(dot(view, normal), 0.0f, 1.0f);
  const float eta = eta_i / eta_t;
  const float sin2_t = eta * eta * std::max(0.0f, 1.0f - cos_i * cos_i);
  if (sin2_t >= 1.0f) {
    result.total_internal = true;
    return result;
  }
  const float cos_t = std::sqrt(1.0f - sin2_t);
  result.reflectance = fresnel_dielectric(cos_i, cos_t, eta_i, eta_t);
  result.direction = normalize(-view * eta + normal * (eta * cos_i - cos_t));
  return result;
}

}  // namespace nodetrace::tracer::detail
