#include "nodetrace/tracer/render/ray_kinds.hpp"

#include <vector>

#include "render/emitters.hpp"
#include "render/path_lobes.hpp"

namespace nodetrace::tracer {

std::string_view ray_kind_name(RayKind kind) {
  switch (kind) {
    case RayKind::Primary: return "primary";
    case RayKind::Shadow: return "shadow";
    case RayKind::Reflection: return "reflection";
    case RayKind::Refraction: return "refraction";
    case RayKind::Diffuse: return "diffuse";
    case RayKind::Glossy: return "glossy";
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

namespace {

// The materials some triangle uses: only they count.
std::vector<const Material*> used_materials(const Scene& scene) {
  std::vector<bool> used(scene.materials.size(), false);
  for (const auto& t : scene.triangles) {
    if (t.material < used.size()) used[t.material] = true;
  }
  std::vector<const Material*> materials;
  for (std::size_t i = 0; i < scene.materials.size(); ++i) {
    if (used[i]) materials.push_back(&scene.materials[i]);
  }
  return materials;
}

}  // namespace

RayKindPlan plan_ray_kinds(const Scene& scene, int max_depth, RayScope scope) {
  RayKindPlan plan;
  plan.kinds = {RayKind::Primary, RayKind::Shadow, RayKind::Reflection, RayKind::Refraction};
  plan.cast[0] = true;
  bool reflects = false, transmits = false;
  for (const Material* material : used_materials(scene)) {
    const Material& m = *material;
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

RayKindPlan plan_path_ray_kinds(const Scene& scene, int max_bounces, bool environment_light) {
  RayKindPlan plan;
  plan.kinds = {RayKind::Primary, RayKind::Shadow,     RayKind::Diffuse,
                RayKind::Glossy,  RayKind::Reflection, RayKind::Refraction};
  bool lit = false, diffuse = false, glossy = false, reflects = false, transmits = false;
  for (const Material* material : used_materials(scene)) {
    const detail::LobeWeights w = detail::lobe_weights(*material);
    lit = lit || w.lit();
    diffuse = diffuse || w.diffuse > 0;
    glossy = glossy || w.glossy > 0 || w.ggx > 0;
    reflects = reflects || w.mirror > 0 || w.dielectric > 0;  // Fresnel and TIR reflect too
    transmits = transmits || w.dielectric > 0;
  }
  const auto decide = [&](RayKind kind, bool needed, const char* why_not, bool bounce) {
    const int k = static_cast<int>(kind);
    plan.cast[k] = needed && (!bounce || max_bounces > 0);
    if (!plan.cast[k]) plan.why_not[k] = !needed ? why_not : "max_bounces is 0";
  };
  decide(RayKind::Primary, true, "", false);
  bool emitter = false;
  for (const Triangle& t : scene.triangles) {
    emitter = emitter || (t.material < scene.materials.size() && detail::emits(scene.materials[t.material]));
    if (emitter) break;
  }
  const bool light = !scene.lights.empty() || emitter || environment_light;
  decide(RayKind::Shadow, lit && light, !light ? "scene has no light" : "no material has a diffuse or glossy lobe",
         false);
  decide(RayKind::Diffuse, diffuse, "no material has a diffuse lobe", true);
  decide(RayKind::Glossy, glossy, "no material has a glossy lobe", true);
  decide(RayKind::Reflection, reflects, "no material reflects or transmits", true);
  decide(RayKind::Refraction, transmits, "no material transmits", true);
  return plan;
}

}  // namespace nodetrace::tracer
