// What one worker of the render loop carries while it renders a chunk of
// pixels (the shader appends records to it), and what the shaders know of a
// hit. Internal header.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include "nodetrace/tracer/render/interaction.hpp"
#include "nodetrace/tracer/render/ray_scheduler.hpp"
#include "nodetrace/tracer/render/render.hpp"
#include "render/sobol_hash_cache.hpp"

namespace nodetrace::tracer {

// A ray tree of depth D may hold up to 2^D rays (reflection and refraction
// at every hit), so its records are not kept whole: once `records` holds
// flush_at, `flush` hands them on in order (waiting, with threads, until
// every earlier chunk has been emitted). Memory per pixel is the recursion,
// O(max depth).
struct Renderer::Context {
  std::vector<formats::Record>* records = nullptr;
  RenderStats stats;
  // Per kind, rays left before the next one timed (render/ray_timing.hpp).
  std::array<std::uint32_t, kRayKindCount> untimed{};
  std::function<void()> flush;
  std::uint64_t flushed = 0;  // records already handed on
  std::size_t flush_at = 0;
  void maybe_flush() {
    if (records && flush && records->size() >= flush_at) flush();
  }

  // Set when each ray's records are kept apart (rays in flight): the shader
  // notes where each ray's records begin and end and which ray cast it.
  std::vector<PixelRays::Ray>* rays = nullptr;
  // Called before each sample of a pixel (Whitted: one) begins its camera
  // ray, when the samples' rays are kept apart (rays in flight: each sample
  // is a tree of its own).
  std::function<void()> begin_sample;
  // Set by Renderer::cast_rays: every ray cast is noted here.
  std::vector<CastRay>* cast = nullptr;
  void note(RayKind kind, const Ray& ray) {
    if (cast) cast->push_back({kind, ray});
  }
  // The ray whose hit the next ray shade() casts depends on.
  std::uint32_t parent = PixelRays::kNoParent;
  // A ray cast by `caster` begins; returns its number in the pixel.
  std::uint32_t begin_ray(std::uint32_t caster) {
    if (!rays) return 0;
    rays->push_back({caster, static_cast<std::uint32_t>(records->size()), 0});
    return static_cast<std::uint32_t>(rays->size() - 1);
  }
  void end_ray(std::uint32_t ray) {
    if (rays) (*rays)[ray].end = static_cast<std::uint32_t>(records->size());
  }
  detail::SobolHashCache sobol_hashes;  // the path tracer's, for --sampler sobol
};

// What both integrators know of a hit: its material, the point, and the
// normals facing the incoming ray.
struct Renderer::ShadingPoint {
  const Material* material = nullptr;
  SurfacePoint surface;
  bool entering = false;  // the ray arrives on the front of the face
  Vec3 facing;            // unit geometric normal towards the incoming ray
  Vec3 normal;            // shading normal (smooth when the scene has vertex normals), same side
  Vec3 view;              // unit direction back along the ray
};

}  // namespace nodetrace::tracer
