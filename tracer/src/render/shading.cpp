// Whitted shading of one pixel: its primary ray, and at each hit the shadow
// rays to the lights in front of the surface, a Phong highlight, then
// reflection and refraction depth-first (docs/ARCHITECTURE.md "What a traversal
// fetches": the order of the records is the order of these rays).
#include <algorithm>
#include <cmath>
#include <limits>

#include "nodetrace/base/portable_math.hpp"
#include "render/fresnel.hpp"
#include "nodetrace/tracer/render/interaction.hpp"
#include "nodetrace/tracer/render/render.hpp"
#include "render/render_context.hpp"

namespace nodetrace::tracer {

// The same results on every machine (portable_math.hpp).
namespace math = base::portable_math;

Vec3 Renderer::shade(const Ray& ray, RayKind kind, int depth, Context& context) const {
  ++context.stats.rays[static_cast<int>(kind)];
  const std::uint32_t self = context.begin_ray(context.parent);
  const auto hit = closest_hit(ray, std::numeric_limits<float>::infinity(), context.records,
                               &context.stats);
  context.end_ray(self);
  context.maybe_flush();
  if (!hit) return scene_.background;

  const Triangle& triangle = scene_.triangles[hit->triangle];
  static const Material kDefaultMaterial;
  const Material& material = triangle.material < scene_.materials.size()
                                 ? scene_.materials[triangle.material]
                                 : kDefaultMaterial;
  const float w = hit->b0;
  // The point from barycentrics lies on the surface more exactly than o + t d,
  // and its error is bounded by the vertices' magnitudes.
  const SurfacePoint surface = interpolate_surface_point(triangle, w, hit->u, hit->v);
  const Vec3& point = surface.point;
  const Vec3 face = face_normals_[hit->triangle];
  const bool entering = dot(ray.direction, face) < 0;
  const Vec3 facing = entering ? face : -face;  // geometric normal towards the incoming ray
  Vec3 normal = facing;
  if (scene_.vertex_normals.size() == scene_.triangles.size() * 3) {
    const Vec3* n = &scene_.vertex_normals[std::size_t{hit->triangle} * 3];
    const Vec3 smooth = n[0] * w + n[1] * hit->u + n[2] * hit->v;
    const float len = length(smooth);
    if (len > 0) normal = dot(smooth, facing) < 0 ? -smooth / len : smooth / len;
  }
  const Vec3 view = -normalize(ray.direction);

  Vec3 color = scene_.ambient * (material.ambient ? *material.ambient : material.diffuse);
  if (plan_.casts(RayKind::Shadow)) {
    const Vec3 shadow_origin = offset_ray_origin(surface, facing);
    const std::size_t lights = options_.first_light_only ? std::min<std::size_t>(1, scene_.lights.size())
                                                         : scene_.lights.size();
    for (std::size_t i = 0; i < lights; ++i) {
      const PointLight& light = scene_.lights[i];
      const Vec3 to_light = light.position - point;
      // A light behind the surface lights nothing here: no ray is needed.
      if (dot(to_light, facing) <= 0) continue;
      ++context.stats.rays[static_cast<int>(RayKind::Shadow)];
      const Ray shadow{shadow_origin, light.position - shadow_origin};
      const std::uint32_t shadow_ray = context.begin_ray(self);
      const bool blocked = occluded(shadow, 1.0f - 1e-4f, context.records, &context.stats);
      context.end_ray(shadow_ray);
      context.maybe_flush();
      if (blocked) continue;
      const Vec3 l = unit_vector(to_light);
      const float diffuse = std::max(0.0f, dot(normal, l));
      float specular = 0;
      if (material.shininess > 0 && (material.specular.x > 0 || material.specular.y > 0 ||
                                     material.specular.z > 0)) {
        specular = math::pow(std::max(0.0f, dot(detail::reflect(-l, normal), view)), material.shininess);
      }
      color += light.color * light_scale_ * (material.diffuse * diffuse + material.specular * specular);
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
  const int x = static_cast<int>(pixel % static_cast<std::uint32_t>(options_.width));
  const int y = static_cast<int>(pixel / static_cast<std::uint32_t>(options_.width));
  context.parent = PixelRays::kNoParent;
  const Vec3 color = shade(pinhole_.primary_ray(x, y), RayKind::Primary, 1, context);
  if (image) image->pixels[pixel] = color;
}

}  // namespace nodetrace::tracer
