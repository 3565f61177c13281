// The kinds of rays a render casts, and which of them a scene needs. One name
// per concept across integrators: a path tracer's camera ray is a primary
// ray, its perfect-mirror and Fresnel-reflected rays are reflection rays, its
// transmitted rays refraction rays; diffuse and glossy rays are its own.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "nodetrace/tracer/scene/scene.hpp"

namespace nodetrace::tracer {

enum class RayKind : std::uint8_t {
  Primary = 0,
  Shadow = 1,
  Reflection = 2,
  Refraction = 3,
  Diffuse = 4,  // path tracing: cosine-weighted bounce
  Glossy = 5,   // path tracing: modified-Phong or GGX lobe bounce
};
inline constexpr int kRayKindCount = 6;
std::string_view ray_kind_name(RayKind kind);

// Which ray kinds a scene needs; the others are never cast, and `why_not`
// says why (e.g. "no light"). `kinds` are the kinds the integrator has at
// all, in the order headers and reports list them (a Whitted render's are
// the first four, so its traces keep the bytes they had before path tracing).
struct RayKindPlan {
  std::array<bool, kRayKindCount> cast{};
  std::array<std::string, kRayKindCount> why_not;
  std::vector<RayKind> kinds;
  bool casts(RayKind kind) const { return cast[static_cast<int>(kind)]; }
};
// Which rays a render traces at most: the primary rays only, those and the
// shadow rays, or the whole Whitted ray tree (the default).
enum class RayScope : std::uint8_t { Primary, PrimaryShadow, Whitted };
std::string_view ray_scope_name(RayScope scope);  // "primary", "primary+shadow", "whitted"

RayKindPlan plan_ray_kinds(const Scene& scene, int max_depth, RayScope scope = RayScope::Whitted);
// The kinds a path tracer with at most `max_bounces` bounce rays after the
// camera ray may cast in `scene` (material lobes: path_lobes.hpp);
// `environment_light`: an environment map that is not black lights it.
RayKindPlan plan_path_ray_kinds(const Scene& scene, int max_bounces, bool environment_light = false);

}  // namespace nodetrace::tracer
