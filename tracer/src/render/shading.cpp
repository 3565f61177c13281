// Whitted shading of one pixel: its primary ray, and at each hit the shadow
// rays to the lights in front of the surface, a Phong highlight (and a GGX
// lobe's light from them, as the path tracer's point lights give it), then
// reflection and refraction depth-first; what both integrators know of a hit;
// a pixel's samples (docs/ARCHITECTURE.md "What a traversal
// fetches": the order of the records is the order of these rays).
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>

#include "nodetrace/base/portable_math.hpp"
#include "render/fresnel.hpp"
#include "render/ggx.hpp"
#include "nodetrace/tracer/render/interaction.hpp"
#include "nodetrace/tracer/render/render.hpp"
#include "render/ray_timing.hpp"
#include "render/render_context.hpp"

namespace nodetrace::tracer {

// The same results on every machine (portable_math.hpp).
namespace math = base::portable_math;

Renderer::ShadingPoint Renderer::shading_point(const Ray& ray, const Hit& hit) const {
  ShadingPoint at;
  const Triangle& triangle = scene_.triangles[hit.triangle];
  static const Material kDefaultMaterial;
  at.material = triangle.material < scene_.materials.size() ? &scene_.materials[triangle.material] : &kDefaultMaterial;
  const float w = hit.b0;
  // The point from barycentrics lies on the surface more exactly than o + t d,
  // and its error is bounded by the vertices' magnitudes.
  at.surface = interpolate_surface_point(triangle, w, hit.u, hit.v);
  const Vec3 face = face_normals_[hit.triangle];
  at.entering = dot(ray.direction, face) < 0;
  at.facing = at.entering ? face : -face;
  at.normal = at.facing;
  if (scene_.vertex_normals.size() == scene_.triangles.size() * 3) {
    const Vec3* n = &scene_.vertex_normals[std::size_t{hit.triangle} * 3];
    const Vec3 smooth = n[0] * w + n[1] * hit.u + n[2] * hit.v;
    const float len = length(smooth);
    if (len > 0) at.normal = dot(smooth, at.facing) < 0 ? -smooth / len : smooth / len;
  }
  at.view = -normalize(ray.direction);
  return at;
}

bool Renderer::light_visible(const Vec3& origin, const PointLight& light, std::uint32_t caster,
                             Context& context) const {
  return point_visible(origin, light.position, caster, context);
}

bool Renderer::point_visible(const Vec3& origin, const Vec3& target, std::uint32_t caster, Context& context) const {
  return shadow_ray_clear({origin, target - origin}, 1.0f - 1e-4f, caster, context);
}

bool Renderer::direction_visible(const Vec3& origin, const Vec3& direction, std::uint32_t caster,
                                 Context& context) const {
  return shadow_ray_clear({origin, direction}, std::numeric_limits<float>::infinity(), caster, context);
}

bool Renderer::shadow_ray_clear(const Ray& shadow, float t_max, std::uint32_t caster, Context& context) const {
  ++context.stats.rays[static_cast<int>(RayKind::Shadow)];
  context.note(RayKind::Shadow, shadow);
  const std::uint32_t shadow_ray = context.begin_ray(caster);
  bool blocked;
  {
    const detail::RayKindTimer timer(context.untimed, context.stats, RayKind::Shadow);
    blocked = occluded(shadow, t_max, context.records, &context.stats);
  }
  context.end_ray(shadow_ray);
  context.maybe_flush();
  return !blocked;
}

Renderer::TracedRay Renderer::cast_closest(const Ray& ray, RayKind kind, Context& context) const {
  ++context.stats.rays[static_cast<int>(kind)];
  context.note(kind, ray);
  const std::uint32_t self = context.begin_ray(context.parent);
  std::optional<Hit> hit;
  {
    const detail::RayKindTimer timer(context.untimed, context.stats, kind);
    hit = closest_hit(ray, std::numeric_limits<float>::infinity(), context.records, &context.stats);
  }
  context.end_ray(self);
  context.maybe_flush();
  return {self, hit};
}

Vec3 Renderer::shade(const Ray& ray, RayKind kind, int depth, Context& context) const {
  const auto [self, hit] = cast_closest(ray, kind, context);
  if (!hit) return scene_.background;

  const ShadingPoint at = shading_point(ray, *hit);
  const Material& material = *at.material;
  const Vec3& point = at.surface.point;
  const SurfacePoint& surface = at.surface;
  const bool entering = at.entering;
  const Vec3& facing = at.facing;
  const Vec3& normal = at.normal;
  const Vec3& view = at.view;

  // An emitter is seen where a ray meets it; it lights nothing else here
  // (no shadow rays go to it: the Whitted tracer's light is its point lights').
  Vec3 color = material.emission + scene_.ambient * (material.ambient ? *material.ambient : material.diffuse);
  if (plan_.casts(RayKind::Shadow)) {
    // A GGX lobe reflects the point lights only, no rays of its own.
    std::optional<detail::GgxLobe> ggx;
    if (detail::lobe_weights(material).ggx > 0) ggx.emplace(detail::ggx_alpha(material.ggx_roughness), normal, view);
    const Vec3 shadow_origin = offset_ray_origin(surface, facing);
    for (std::size_t i = 0; i < lights_shadowed_; ++i) {
      const PointLight& light = scene_.lights[i];
      const Vec3 to_light = light.position - point;
      // A light behind the surface lights nothing here: no ray is needed.
      if (dot(to_light, facing) <= 0) continue;
      if (!light_visible(shadow_origin, light, self, context)) continue;
      const Vec3 l = unit_vector(to_light);
      const float diffuse = std::max(0.0f, dot(normal, l));
      float specular = 0;
      if (material.shininess > 0 && (material.specular.x > 0 || material.specular.y > 0 ||
                                     material.specular.z > 0)) {
        specular = math::pow(std::max(0.0f, dot(detail::reflect(-l, normal), view)), material.shininess);
      }
      color += light.color * light_scale_ * (material.diffuse * diffuse + material.specular * specular);
      if (ggx) color += light.color * material.ggx_color * (light_scale_ * ggx->point_light(l));
    }
  }
  if (depth >= options_.max_depth) return color;

  float reflect_weight = plan_.casts(RayKind::Reflection) ? material.reflectance : 0.0f;
  float refract_weight = 0;
  Vec3 refracted;
  if (plan_.casts(RayKind::Refraction) && material.transmittance > 0) {
    const float eta_i = entering ? 1.0f : material.ior, eta_t = entering ? material.ior : 1.0f;
    const detail::Refraction refraction = detail::refract(view, normal, eta_i, eta_t);
    if (refraction.total_internal) {
      reflect_weight += material.transmittance;
    } else {
      reflect_weight += material.transmittance * refraction.reflectance;
      refract_weight = material.transmittance * (1.0f - refraction.reflectance);
      refracted = refraction.direction;
    }
  }
  if (reflect_weight > 0 && plan_.casts(RayKind::Reflection)) {
    Vec3 direction = detail::reflect(ray.direction, normal);
    // A smooth normal can send the mirror ray under the surface: use the face.
    if (dot(direction, facing) <= 0) direction = detail::reflect(ray.direction, facing);
    const Ray reflection{offset_ray_origin(surface, facing), normalize(direction)};
    context.parent = self;
    color += shade(reflection, RayKind::Reflection, depth + 1, context) * reflect_weight;
  }
  if (refract_weight > 0 && dot(refracted, facing) < 0) {
    const Ray refraction{offset_ray_origin(surface, -facing), refracted};
    context.parent = self;
    color += shade(refraction, RayKind::Refraction, depth + 1, context) * refract_weight;
  }
  return color;
}

void Renderer::render_pixel(std::uint32_t pixel, Context& context, Image* image) const {
  if (options_.integrator == Integrator::Path) {
    // Welford's running mean and variance, in double, in sample order.
    std::array<double, 3> mean{}, m2{};
    const std::uint32_t samples = options_.path.samples_per_pixel;
    for (std::uint32_t s = 0; s < samples; ++s) {
      if (context.begin_sample) context.begin_sample();
      context.parent = PixelRays::kNoParent;
      const Vec3 radiance = trace_path(pixel, s, context);
      for (int c = 0; c < 3; ++c) {
        const double delta = double(radiance[c]) - mean[c];
        mean[c] += delta / double(s + 1);
        m2[c] += delta * (double(radiance[c]) - mean[c]);
      }
    }
    if (image) {
      image->pixels[pixel] = {float(mean[0]), float(mean[1]), float(mean[2])};
      if (samples > 1) {
        const double n = double(samples - 1);
        image->variance[pixel] = {float(m2[0] / n), float(m2[1] / n), float(m2[2] / n)};
      }
    }
    return;
  }
  const int x = static_cast<int>(pixel % static_cast<std::uint32_t>(options_.width));
  const int y = static_cast<int>(pixel / static_cast<std::uint32_t>(options_.width));
  if (context.begin_sample) context.begin_sample();
  context.parent = PixelRays::kNoParent;
  const Vec3 color = shade(pinhole_.primary_ray(x, y), RayKind::Primary, 1, context);
  if (image) image->pixels[pixel] = color;
}

void Renderer::prepare_image(Image& image) const {
  image.width = options_.width;
  image.height = options_.height;
  const std::size_t pixels = static_cast<std::size_t>(options_.width) * static_cast<std::size_t>(options_.height);
  image.pixels.assign(pixels, Vec3{});
  const bool path = options_.integrator == Integrator::Path;
  image.variance.assign(path ? pixels : 0, Vec3{});
  image.linear_radiance = path;
}

}  // namespace nodetrace::tracer
