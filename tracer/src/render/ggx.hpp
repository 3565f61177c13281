// The GGX microfacet lobe: Blender Cycles' Glossy BSDF with distribution GGX
// as Blender 3.4 computes it (intern/cycles/kernel/closure/bsdf_microfacet.h,
// after Walter et al., "Microfacet Models for Refraction through Rough
// Surfaces", EGSR 2007), so scripts/test-cycles.sh can hold ours to it:
//   alpha = roughness^2 (the node's Roughness squared, svm_closure.h),
//   D(h) = alpha^2 / (pi (1 + (alpha^2 - 1) cos^2 theta_h)^2),
//   G1(w) = 2 / (1 + sqrt(1 + alpha^2 tan^2 theta_w)), separable G = G1(v) G1(l),
//   no Fresnel term (the node's colour is the reflectance), and
//   BRDF x cos theta_l = colour D G / (4 cos theta_v),
// zero unless view and light are both above the shading normal. Single
// scattering: light that would leave after several microfacets is lost, as
// in Cycles' GGX (its Multiscatter GGX is another distribution).
// Directions are drawn from the distribution of visible normals (Heitz,
// "Sampling the GGX Distribution of Visible Normals", JCGT 2018) and
// reflected about the drawn normal. Internal header of the path tracer.
#pragma once

#include "nodetrace/tracer/geometry/vec3.hpp"
#include "render/path_lobes.hpp"

namespace nodetrace::tracer::detail {

// The smallest alpha the lobe uses: roughness below 0.01 counts as 0.01. A
// narrower lobe's D overflows float precision near its peak (Cycles renders
// roughness up to about 0.018, alpha^2 <= 1e-7, as a sharp mirror instead).
inline constexpr float kMinGgxAlpha = 1e-4f;

// alpha of a roughness: its square, at least kMinGgxAlpha.
float ggx_alpha(float roughness);

// The lobe at one shading point: unit normal and unit direction to the viewer.
class GgxLobe {
 public:
  GgxLobe(float alpha, const Vec3& normal, const Vec3& view);

  // The BRDF times cos theta_l, without the colour, towards the unit
  // direction `light`: D G / (4 cos theta_v); 0 unless both are above the normal.
  float brdf_cos(const Vec3& light) const;

  // What a point light in the unit direction `light` gives, per unit of its
  // colour, under the scene files' convention that a Lambertian surface of
  // colour Kd gives Kd cos theta: pi x brdf_cos.
  float point_light(const Vec3& light) const;

  // The density (per solid angle) of sample()'s directions at the unit
  // direction `light`: G1(v) D(h) / (4 cos theta_v), over the whole sphere
  // (sample() sends some directions below the surface, where the lobe gives
  // nothing), so it integrates to 1.
  float pdf(const Vec3& light) const;

  // A unit direction reflected about a visible microfacet normal drawn from
  // two uniform numbers in [0, 1). Where it is above the surface, its
  // brdf_cos / pdf is masking(direction).
  Vec3 sample(float u1, float u2) const;

  // G1 of a unit direction above the surface.
  float masking(const Vec3& direction) const;

  // The viewer is above the normal: the lobe reflects something.
  bool facing() const { return cos_view_ > 0; }

 private:
  float distribution(const Vec3& half) const;  // D

  float alpha_, alpha2_;
  Frame frame_;
  Vec3 view_;
  float cos_view_, masking_view_;
};

}  // namespace nodetrace::tracer::detail
