// The lobes of a material under path tracing and how a bounce draws one
// direction from a lobe. Internal header of the path tracer.
//
// Mixture rule: a material is the sum Whitted shading adds up, local colour
// plus reflectance x mirror plus transmittance x dielectric, with the local
// colour as the BRDF Kd / pi + Ks (n + 2) / (2 pi) cos^n(alpha) (Lafortune and
// Willems' modified Phong, alpha the angle to the mirror direction), plus the
// GGX microfacet lobe of a material that has one (ggx.hpp). Each bounce picks
// one lobe with probability proportional to its weight below and divides
// what the lobe carries by that probability: an unbiased estimate of the sum.
#pragma once

#include "nodetrace/tracer/geometry/vec3.hpp"
#include "nodetrace/tracer/scene/scene.hpp"

namespace nodetrace::tracer::detail {

struct LobeWeights {
  float diffuse = 0;     // mean of Kd
  float glossy = 0;      // mean of Ks, when the shininess is positive
  float mirror = 0;      // reflectance
  float dielectric = 0;  // transmittance: Fresnel then picks reflection or refraction
  float ggx = 0;         // mean of the GGX colour, when the roughness is positive
  // Last in the sum, so a material without a GGX lobe sums as before (x + 0 is x).
  float total() const { return diffuse + glossy + mirror + dielectric + ggx; }
  // The lobes next-event estimation serves: the point lights, emitters and
  // environment map light them.
  bool lit() const { return diffuse > 0 || glossy > 0 || ggx > 0; }
};

// An orthonormal basis with `normal` (unit) as its z axis.
struct Frame {
  explicit Frame(const Vec3& n);
  Vec3 to_world(const Vec3& local) const { return tangent * local.x + bitangent * local.y + normal * local.z; }
  Vec3 to_local(const Vec3& v) const { return {dot(v, tangent), dot(v, bitangent), dot(v, normal)}; }
  Vec3 tangent, bitangent, normal;
};

// Negative and NaN weights count as 0.
LobeWeights lobe_weights(const Material& material);

// A unit direction with density cos(theta) / pi about the unit normal `n`,
// from two uniform numbers in [0, 1).
Vec3 sample_cosine(const Vec3& n, float u1, float u2);

// A unit direction with density (e + 1) / (2 pi) cos^e(alpha) about the unit
// direction `axis`, from two uniform numbers in [0, 1).
Vec3 sample_phong(const Vec3& axis, float exponent, float u1, float u2);

}  // namespace nodetrace::tracer::detail
