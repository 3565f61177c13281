// One path of the path tracer (--integrator path). The camera ray passes
// through a random point of the pixel; at each hit, next-event estimation
// casts one shadow ray per light in front of the surface (as the Whitted
// tracer does) when the material has a diffuse or glossy lobe, then one
// bounce ray from one lobe (path_lobes.hpp) continues the path. A path that
// escapes collects the background: it is light from every direction (an
// environment). Point lights follow the scene files' convention that the
// Whitted tracer uses: no fall-off with distance, N lights of 1 / sqrt(N)
// each, and a Lambertian surface of colour Kd lit at angle theta reflects
// Kd cos(theta) times the light. The ambient term is kept, added at every
// hit as the Whitted tracer adds it: the scene files light with it (BART
// Robot's one light is enclosed, so without it Robot is black). Record
// order: each ray's fetches when it is cast, shadow rays before the bounce
// ray of their hit.
#include <algorithm>
#include <array>
#include <cmath>

#include "nodetrace/base/portable_math.hpp"
#include "nodetrace/tracer/render/render.hpp"
#include "render/fresnel.hpp"
#include "render/path_lobes.hpp"
#include "render/path_random.hpp"
#include "render/render_context.hpp"

namespace nodetrace::tracer {

namespace math = base::portable_math;  // the same rays on every machine

namespace {

bool finite(const Vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
float largest_component(const Vec3& v) { return std::max({v.x, v.y, v.z}); }

// The bounce's lobe: the first whose share of the weights' running sum
// reaches `pick`; rounding can never choose a lobe of weight 0.
int choose_lobe(const std::array<float, 4>& weights, float pick) {
  float sum = 0;
  int last = -1;
  for (int i = 0; i < 4; ++i) {
    if (!(weights[i] > 0)) continue;
    sum += weights[i];
    last = i;
    if (pick < sum) return i;
  }
  return last;
}

}  // namespace

Vec3 Renderer::trace_path(std::uint32_t pixel, std::uint32_t sample, Context& context) const {
  const detail::PathRandom random(options_.animation_frame, pixel, sample);
  const std::uint32_t width = static_cast<std::uint32_t>(options_.width);
  Ray ray = pinhole_.ray_through(float(pixel % width) + random.uniform(0, detail::kPixelX),
                                 float(pixel / width) + random.uniform(0, detail::kPixelY));
  RayKind kind = RayKind::Primary;
  Vec3 radiance, throughput{1, 1, 1};
  const auto dropped = [&] {
    ++context.stats.nonfinite_samples;
    return Vec3{};
  };
  for (int bounce = 0;; ++bounce) {
    const auto [self, hit] = cast_closest(ray, kind, context);
    if (!hit) {
      radiance += throughput * scene_.background;
      break;
    }
    const ShadingPoint at = shading_point(ray, *hit);
    const Material& material = *at.material;
    const detail::LobeWeights w = detail::lobe_weights(material);
    radiance += throughput * scene_.ambient * (material.ambient ? *material.ambient : material.diffuse);

    // Next-event estimation: the diffuse and glossy lobes' light from each
    // point light (the mirror and dielectric lobes see none: a point is never hit).
    if ((w.diffuse > 0 || w.glossy > 0) && plan_.casts(RayKind::Shadow)) {
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
      }
    }
    if (bounce >= options_.path.max_bounces) break;

    // The bounce ray: number bounce + 1 of the path.
    const auto next = static_cast<std::uint32_t>(bounce + 1);
    const float total = w.total();
    if (!(total > 0)) break;  // a black material ends the path
    if (next >= static_cast<std::uint32_t>(kRouletteFromBounce)) {
      const float survival = std::min(kMaxSurvival, largest_component(throughput));
      if (!(random.uniform(next, detail::kRoulette) < survival)) break;
      throughput = throughput / survival;
    }
    const int lobe = choose_lobe({w.diffuse, w.glossy, w.mirror, w.dielectric},
                                 random.uniform(next, detail::kLobe) * total);
    const float u1 = random.uniform(next, detail::kDirection1), u2 = random.uniform(next, detail::kDirection2);
    Vec3 direction, weight;
    bool leaves_front = true;  // the ray leaves on the side the path came from
    if (lobe == 0) {
      kind = RayKind::Diffuse;
      direction = detail::sample_cosine(at.normal, u1, u2);
      weight = material.diffuse * (total / w.diffuse);
    } else if (lobe == 1) {
      kind = RayKind::Glossy;
      const Vec3 mirror = normalize(detail::reflect(ray.direction, at.normal));
      direction = detail::sample_phong(mirror, material.shininess, u1, u2);
      const float cos_out = dot(direction, at.normal);
      if (!(cos_out > 0)) break;  // below the surface: the lobe gives nothing
      const float n = material.shininess;
      weight = material.specular * ((n + 2.0f) / (n + 1.0f) * cos_out * (total / w.glossy));
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
