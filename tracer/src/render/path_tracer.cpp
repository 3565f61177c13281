// One path of the path tracer (--integrator path). The camera ray passes
// through a random point of the pixel; at each hit, next-event estimation
// casts one shadow ray per light in front of the surface (as the Whitted
// tracer does) when the material has a diffuse, glossy or GGX lobe, then one
// bounce ray from one lobe (path_lobes.hpp) continues the path. A path that
// escapes collects the background: it is light from every direction (an
// environment). Point lights follow the scene files' convention that the
// Whitted tracer uses: no fall-off with distance, N lights of 1 / sqrt(N)
// each, and a Lambertian surface of colour Kd lit at angle theta reflects
// Kd cos(theta) times the light. The ambient term is kept, added at every
// hit as the Whitted tracer adds it: the scene files light with it (BART
// Robot's one light is enclosed, so without it Robot is black).
// Emissive triangles (emitters.hpp) are area lights in physical units: a ray
// that meets one collects its radiance, and next-event estimation casts one
// more shadow ray, to a point on an emitter chosen by power; the two
// estimates of a diffuse, glossy or GGX lobe's light are combined with
// multiple importance sampling (Veach's power heuristic, per lobe: the
// bounce ray's density is its lobe's choice probability times the lobe's
// density). Record order: each ray's fetches when it is cast, shadow rays
// before the bounce ray of their hit, the emitter's after the point lights'.
// An environment map (--environment, environment_map.hpp) replaces the
// background: a ray that escapes collects the map's radiance in its
// direction, and next-event estimation casts one more shadow ray, unbounded,
// in a direction drawn from the map's distribution (after the emitter's),
// combined with the bounce ray by the same power heuristic.
// A GGX lobe (ggx.hpp) is lit as the diffuse and glossy lobes are: by the
// point lights (GgxLobe::point_light), the emitters and the map, each
// combined with its bounce ray by the power heuristic.
#include <algorithm>
#include <array>
#include <cmath>
#include <optional>

#include "nodetrace/base/portable_math.hpp"
#include "nodetrace/tracer/render/render.hpp"
#include "render/emitters.hpp"
#include "render/fresnel.hpp"
#include "render/ggx.hpp"
#include "render/path_lobes.hpp"
#include "render/path_random.hpp"
#include "render/render_context.hpp"

namespace nodetrace::tracer {

namespace math = base::portable_math;  // the same rays on every machine

namespace {

bool finite(const Vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
float largest_component(const Vec3& v) { return std::max({v.x, v.y, v.z}); }

constexpr float kInvPi = 0.318309886183790671538f;

// Veach's power heuristic (beta 2) for the strategy of density `own`
// against the other's `other`.
float power_heuristic(float own, float other) {
  const float a = own * own, b = other * other;
  return a + b > 0 ? a / (a + b) : 0.0f;
}

// The glossy lobe's BRDF without Ks, (n + 2) / (2 pi) cos^n(alpha), and the
// density of its sampled directions, (n + 1) / (2 pi) cos^n(alpha).
float phong_cos_power(float cos_alpha, float n) { return cos_alpha > 0 ? math::pow(cos_alpha, n) : 0.0f; }

// The bounce's lobe: the first whose share of the weights' running sum
// reaches `pick`; rounding can never choose a lobe of weight 0.
int choose_lobe(const std::array<float, 5>& weights, float pick) {
  float sum = 0;
  int last = -1;
  for (int i = 0; i < 5; ++i) {
    if (!(weights[i] > 0)) continue;
    sum += weights[i];
    last = i;
    if (pick < sum) return i;
  }
  return last;
}

}  // namespace

Vec3 Renderer::trace_path(std::uint32_t pixel, std::uint32_t sample, Context& context) const {
  const detail::PathRandom random(options_.animation_frame, pixel, sample, options_.path.sampler,
                                  options_.path.samples_per_pixel, options_.path.seed, &context.sobol_hashes);
  const std::uint32_t width = static_cast<std::uint32_t>(options_.width);
  const auto in_pixel = random.uniform_pair(0, detail::kPixelX);
  Ray ray = pinhole_.ray_through(float(pixel % width) + in_pixel.first, float(pixel / width) + in_pixel.second);
  RayKind kind = RayKind::Primary;
  Vec3 radiance, throughput{1, 1, 1};
  // Next-event estimation to emitters and to the environment map happens at
  // each diffuse, glossy or GGX hit that casts shadow rays; `bounce_density`
  // is the density (per solid angle) of the last bounce ray's direction when
  // it came from such a hit and such a lobe (0: a camera, mirror or
  // dielectric ray, whose emitters and map are met only by the ray).
  const bool sample_emitters = emitters_ && !emitters_->empty() && plan_.casts(RayKind::Shadow);
  const EnvironmentMap* environment = options_.environment.get();
  const bool sample_environment = environment && environment->lights() && plan_.casts(RayKind::Shadow);
  const bool next_event = sample_emitters || sample_environment;
  float bounce_density = 0;
  const auto dropped = [&] {
    ++context.stats.nonfinite_samples;
    return Vec3{};
  };
  for (int bounce = 0;; ++bounce) {
    const auto [self, hit] = cast_closest(ray, kind, context);
    if (!hit) {
      if (environment) {
        const EnvironmentMap::LookUp seen = environment->look_up(ray.direction);
        const float weight = sample_environment && bounce_density > 0 ? power_heuristic(bounce_density, seen.pdf) : 1.0f;
        radiance += throughput * seen.radiance * weight;
      } else {
        radiance += throughput * scene_.background;
      }
      break;
    }
    const ShadingPoint at = shading_point(ray, *hit);
    const Material& material = *at.material;
    const detail::LobeWeights w = detail::lobe_weights(material);
    // Built only for a material that has the lobe: its frame and masking cost every hit otherwise.
    std::optional<detail::GgxLobe> ggx;
    if (w.ggx > 0) ggx.emplace(detail::ggx_alpha(material.ggx_roughness), at.normal, at.view);
    radiance += throughput * scene_.ambient * (material.ambient ? *material.ambient : material.diffuse);
    if (detail::emits(material)) {
      float weight = 1;
      if (bounce_density > 0) {
        const float cos_emitter = std::fabs(dot(face_normals_[hit->triangle], ray.direction));
        const float emitter_density = emitters_->pdf_area(hit->triangle) * hit->t * hit->t / cos_emitter;
        weight = cos_emitter > 0 ? power_heuristic(bounce_density, emitter_density) : 0.0f;
      }
      radiance += throughput * material.emission * weight;
    }

    // Next-event estimation: the diffuse, glossy and GGX lobes' light from each
    // point light (the mirror and dielectric lobes see none: a point is never hit).
    if (w.lit() && plan_.casts(RayKind::Shadow)) {
      const Vec3 shadow_origin = offset_ray_origin(at.surface, at.facing);
      for (std::size_t i = 0; i < lights_shadowed_; ++i) {
        const PointLight& light = scene_.lights[i];
        const Vec3 to_light = light.position - at.surface.point;
        if (dot(to_light, at.facing) <= 0) continue;  // behind the surface: no ray
        if (!light_visible(shadow_origin, light, self, context)) continue;
        const Vec3 l = unit_vector(to_light);
        const float cos_light = dot(at.normal, l);
        if (!(cos_light > 0)) continue;
        Vec3 reflectance = w.diffuse > 0 ? material.diffuse : Vec3{};
        if (w.glossy > 0) {
          const float cos_alpha = std::max(0.0f, dot(detail::reflect(-l, at.normal), at.view));
          const float n = material.shininess;
          reflectance += material.specular * ((n + 2.0f) * 0.5f * math::pow(cos_alpha, n));
        }
        radiance += throughput * light.color * reflectance * (light_scale_ * cos_light);
        if (w.ggx > 0) {
          radiance += throughput * light.color * material.ggx_color * (light_scale_ * ggx->point_light(l));
        }
      }
    }
    const auto next_ray = static_cast<std::uint32_t>(bounce + 1);
    // Where no bounce ray follows, a light sample's estimate is the only one.
    const bool last = bounce >= options_.path.max_bounces;
    // The diffuse, glossy and GGX lobes' BRDF x cos towards a light sample in
    // unit direction `l` of density `light_density` (per solid angle), each
    // lobe weighted against its bounce ray.
    const auto weighted_brdf_cos = [&](const Vec3& l, float cos_surface, float light_density) {
      const float total = w.total();
      Vec3 brdf_cos;
      if (w.diffuse > 0) {
        const float lobe_density = w.diffuse / total * cos_surface * kInvPi;
        const float weight = last ? 1.0f : power_heuristic(light_density, lobe_density);
        brdf_cos += material.diffuse * (kInvPi * cos_surface * weight);
      }
      if (w.glossy > 0) {
        const float n = material.shininess;
        const float lobe = phong_cos_power(dot(detail::reflect(-l, at.normal), at.view), n) * 0.5f * kInvPi;
        const float lobe_density = w.glossy / total * (n + 1.0f) * lobe;
        const float weight = last ? 1.0f : power_heuristic(light_density, lobe_density);
        brdf_cos += material.specular * ((n + 2.0f) * lobe * cos_surface * weight);
      }
      if (w.ggx > 0) {
        const float lobe_density = w.ggx / total * ggx->pdf(l);
        const float weight = last ? 1.0f : power_heuristic(light_density, lobe_density);
        brdf_cos += material.ggx_color * (ggx->brdf_cos(l) * weight);
      }
      return brdf_cos;
    };
    if (w.lit() && sample_emitters) {
      const auto on_emitter = random.uniform_pair(next_ray, detail::kEmitterU);
      const detail::Emitters::Sample e = emitters_->sample(on_emitter.first, on_emitter.second);
      const Vec3 to_emitter = e.point - at.surface.point;
      const float distance2 = dot(to_emitter, to_emitter);
      if (dot(to_emitter, at.facing) > 0 && distance2 > 0 &&
          point_visible(offset_ray_origin(at.surface, at.facing), e.point, self, context)) {
        const Vec3 l = to_emitter / std::sqrt(distance2);
        const float cos_surface = dot(at.normal, l), cos_emitter = std::fabs(dot(e.normal, l));
        const float emitter_density = e.pdf_area * distance2 / cos_emitter;
        if (cos_surface > 0 && cos_emitter > 0 && emitter_density > 0) {
          radiance += throughput * e.radiance * weighted_brdf_cos(l, cos_surface, emitter_density) / emitter_density;
        }
      }
    }
    if (w.lit() && sample_environment) {
      const EnvironmentMap::Sample s = environment->sample(random.uniform(next_ray, detail::kEnvironmentU),
                                                           random.uniform(next_ray, detail::kEnvironmentV));
      if (dot(s.direction, at.facing) > 0 && s.pdf > 0 &&
          direction_visible(offset_ray_origin(at.surface, at.facing), s.direction, self, context)) {
        const float cos_surface = dot(at.normal, s.direction);
        if (cos_surface > 0) {
          radiance += throughput * s.radiance * weighted_brdf_cos(s.direction, cos_surface, s.pdf) / s.pdf;
        }
      }
    }
    if (bounce >= options_.path.max_bounces) break;

    // The bounce ray: number bounce + 1 of the path.
    const std::uint32_t next = next_ray;
    const float total = w.total();
    if (!(total > 0)) break;  // a black material ends the path
    if (next >= static_cast<std::uint32_t>(kRouletteFromBounce)) {
      const float survival = std::min(kMaxSurvival, largest_component(throughput));
      if (!(random.uniform(next, detail::kRoulette) < survival)) break;
      throughput = throughput / survival;
    }
    const int lobe = choose_lobe({w.diffuse, w.glossy, w.mirror, w.dielectric, w.ggx},
                                 random.uniform(next, detail::kLobe) * total);
    const auto [u1, u2] = random.uniform_pair(next, detail::kDirection1);
    Vec3 direction, weight;
    bool leaves_front = true;  // the ray leaves on the side the path came from
    bounce_density = 0;
    if (lobe == 0) {
      kind = RayKind::Diffuse;
      direction = detail::sample_cosine(at.normal, u1, u2);
      weight = material.diffuse * (total / w.diffuse);
      if (next_event) bounce_density = w.diffuse / total * std::max(0.0f, dot(direction, at.normal)) * kInvPi;
    } else if (lobe == 1) {
      kind = RayKind::Glossy;
      const Vec3 mirror = normalize(detail::reflect(ray.direction, at.normal));
      direction = detail::sample_phong(mirror, material.shininess, u1, u2);
      const float cos_out = dot(direction, at.normal);
      if (!(cos_out > 0)) break;  // below the surface: the lobe gives nothing
      const float n = material.shininess;
      weight = material.specular * ((n + 2.0f) / (n + 1.0f) * cos_out * (total / w.glossy));
      if (next_event) {
        bounce_density = w.glossy / total * (n + 1.0f) * 0.5f * kInvPi * phong_cos_power(dot(direction, mirror), n);
      }
    } else if (lobe == 4) {
      kind = RayKind::Glossy;
      if (!ggx->facing()) break;  // the viewer below the shading normal: the lobe gives nothing
      direction = ggx->sample(u1, u2);
      if (!(dot(direction, at.normal) > 0)) break;  // below the surface: the lobe gives nothing
      // BRDF x cos over the density: G1 of the direction.
      weight = material.ggx_color * (ggx->masking(direction) * (total / w.ggx));
      if (next_event) bounce_density = w.ggx / total * ggx->pdf(direction);
    } else {
      kind = RayKind::Reflection;
      // The lobe's weight (reflectance or transmittance) over its probability
      // (that weight over the total); Fresnel's F or 1 - F cancels its own choice.
      weight = Vec3{1, 1, 1} * total;
      bool reflects = true;
      if (lobe == 3) {
        const float eta_i = at.entering ? 1.0f : material.ior, eta_t = at.entering ? material.ior : 1.0f;
        const detail::Refraction refraction = detail::refract(at.view, at.normal, eta_i, eta_t);
        // Fresnel chooses: reflected with probability F, else refracted.
        reflects = refraction.total_internal || random.uniform(next, detail::kFresnel) < refraction.reflectance;
        if (!reflects) {
          kind = RayKind::Refraction;
          direction = refraction.direction;
          leaves_front = false;
        }
      }
      if (reflects) {
        direction = detail::reflect(ray.direction, at.normal);
        // A smooth normal can send the mirror ray under the surface: use the face.
        if (dot(direction, at.facing) <= 0) direction = detail::reflect(ray.direction, at.facing);
        direction = normalize(direction);
      }
    }
    throughput = throughput * weight;
    if (!finite(throughput) || !finite(direction)) return dropped();
    // A direction on the wrong side of the face would start inside it.
    if (leaves_front ? !(dot(direction, at.facing) > 0) : !(dot(direction, at.facing) < 0)) break;
    ray = {offset_ray_origin(at.surface, leaves_front ? at.facing : -at.facing), direction};
    context.parent = self;
  }
  return finite(radiance) ? radiance : dropped();
}

}  // namespace nodetrace::tracer
