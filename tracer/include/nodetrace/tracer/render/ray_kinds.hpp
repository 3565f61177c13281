// The kinds of rays a Whitted render casts, and which of them a scene needs.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <string_view>

#include "nodetrace/tracer/scene/scene.hpp"

namespace nodetrace::tracer {

enum class RayKind : std::uint8_t { Primary = 0, Shadow = 1, Reflection = 2, Refraction = 3 };
inline constexpr int kRayKindCount = 4;
std::string_view ray_kind_name(RayKind kind);

// Which ray kinds a scene needs; the others are never cast, and `why_not`
// says why (e.g. "no light").
struct RayKindPlan {
  std::array<bool, kRayKindCount> cast{};
  std::array<std::string, kRayKindCount> why_not;
  bool casts(RayKind kind) const { return cast[static_cast<int>(kind)]; }
};
// Which rays a render traces at most: the primary rays only, those and the
// shadow rays, or the whole Whitted ray tree (the default).
enum class RayScope : std::uint8_t { Primary, PrimaryShadow, Whitted };
std::string_view ray_scope_name(RayScope scope);  // "primary", "primary+shadow", "whitted"

RayKindPlan plan_ray_kinds(const Scene& scene, int max_depth, RayScope scope = RayScope::Whitted);

}  // namespace nodetrace::tracer
