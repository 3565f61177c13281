#include "nodetrace/tracer/render/ray_kinds.hpp"

#include <vector>

namespace nodetrace::tracer {

std::string_view ray_kind_name(RayKind kind) {
  switch (kind) {
    case RayKind::Primary: return "primary";
    case RayKind::Shadow: return "shadow";
    case RayKind::Reflection: return "reflection";
    case RayKind::Refraction: return "refraction";
  }
  return "primary";
}

std::string_view ray_scope_name(RayScope scope) {
  switch (scope) {
    case RayScope::Primary: return "primary";
    case RayScope::PrimaryShadow: return "primary+shadow";
    case RayScope::Whitted: return "whitted";
  }
  return "whitted";
}

RayKindPlan plan_ray_kinds(const Scene& scene, int max_depth, RayScope scope) {
  RayKindPlan plan;
  plan.cast[0] = true;
  bool reflects = false, transmits = false;
  // Only the materials some triangle uses count.
  std::vector<bool> used(scene.materials.size(), false);
  for (const auto& t : scene.triangles) {
    if (t.material < used.size()) used[t.material] = true;
  }
  for (std::size_t i = 0; i < scene.materials.size(); ++i) {
    if (!used[i]) continue;
    const Material& m = scene.materials[i];
    reflects = reflects || m.reflectance > 0 || m.transmittance > 0;  // Fresnel and TIR reflect too
    transmits = transmits || m.transmittance > 0;
  }
  plan.cast[1] = !scene.lights.empty();
  if (!plan.cast[1]) plan.why_not[1] = "scene has no light";
  plan.cast[2] = reflects && max_depth > 1;
  if (!plan.cast[2]) {
    plan.why_not[2] = !reflects ? "no material reflects or transmits" : "max_depth is 1";
  }
  plan.cast[3] = transmits && max_depth > 1;
  if (!plan.cast[3]) plan.why_not[3] = !transmits ? "no material transmits" : "max_depth is 1";
  // A narrower scope leaves out kinds the scene would need; the reason names it.
  if (scope != RayScope::Whitted) {
    const std::string narrowed = "rays limited to " + std::string(ray_scope_name(scope));
    for (int k = scope == RayScope::Primary ? 1 : 2; k < kRayKindCount; ++k) {
      if (plan.cast[k]) {
        plan.cast[k] = false;
        plan.why_not[k] = narrowed;
      }
    }
  }
  return plan;
}

}  // namespace nodetrace::tracer
