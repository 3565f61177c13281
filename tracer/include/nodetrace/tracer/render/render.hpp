// The renderer: the Whitted ray tracer (pinhole primary rays, shadow rays to
// the lights, mirror reflection and refraction: Snell, Fresnel, total
// internal reflection) or a path tracer (--integrator path: path_tracer.cpp),
// over an acceleration structure (kd-tree or BVH) stored in a given layout.
// Every traversal
// records the node fetches it makes (docs/ARCHITECTURE.md "What a traversal fetches").
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "nodetrace/formats/record/record.hpp"
#include "nodetrace/tracer/accel/acceleration_structure.hpp"
#include "nodetrace/tracer/render/camera.hpp"
#include "nodetrace/tracer/render/environment_map.hpp"
#include "nodetrace/tracer/render/image.hpp"
#include "nodetrace/tracer/render/integrator.hpp"
#include "nodetrace/tracer/accel/kdtree.hpp"
#include "nodetrace/tracer/accel/layout.hpp"
#include "nodetrace/tracer/render/pixel_order.hpp"
#include "nodetrace/tracer/geometry/ray.hpp"
#include "nodetrace/tracer/render/ray_kinds.hpp"
#include "nodetrace/tracer/render/ray_scheduler.hpp"
#include "nodetrace/tracer/render/render_stats.hpp"
#include "nodetrace/tracer/scene/scene.hpp"
#include "nodetrace/tracer/accel/traversal.hpp"

namespace nodetrace::tracer {

namespace detail {
class Emitters;
}

struct RenderOptions {
  int width = 800, height = 600;
  Integrator integrator = Integrator::Whitted;
  PathOptions path;  // the path tracer's (Integrator::Path only)
  // Path tracing: the light of the directions rays escape in, instead of
  // the scene's constant background (null: the background).
  std::shared_ptr<const EnvironmentMap> environment;
  // The animation frame rendered: the path tracer's random numbers depend on it.
  std::uint64_t animation_frame = 0;
  int max_depth = 10;  // Whitted: primary rays are depth 1; no secondary ray beyond it
  RayScope rays = RayScope::Whitted;  // which kinds of rays are traced at most
  bool first_light_only = false;      // shadow rays to the scene's first light only
  PixelOrder pixel_order = PixelOrder::Scanline;
  int tile_size = 8;
  std::optional<Camera> camera;  // overrides the scene's camera
  std::optional<float> fov_y_degrees;  // overrides the field of view of the camera used
  unsigned threads = 0;          // 0: one per core
  bool record = true;            // false: render only (no records made)
  StreamSelection streams;
  AddressMap addresses;
  int pixels_per_chunk = 512;  // unit of parallel work (does not change the output)
  // Rays in flight (docs/guide/rays-in-flight.md, ray_scheduler.hpp): units of
  // this many ray slots each. Pixel-sequence positions are dealt to the
  // units in runs of unit_pixels, run r to unit r mod units. One unit of one
  // slot is the sequential order.
  unsigned rays_in_flight = 1;
  unsigned units = 1;
  unsigned unit_pixels = 64;
  ReadyOrder ready_order = ReadyOrder::DepthFirst;
  // A chunk's records go to the sink once this many are waiting, even in the
  // middle of a pixel, so memory does not grow with the ray tree (does not
  // change the output; a sink call may hold one traversal more).
  std::size_t records_per_flush = std::size_t{1} << 18;
};

class Renderer {
 public:
  using RecordCallback = std::function<void(std::span<const formats::Record>)>;
  using Progress = std::function<void(double fraction_done)>;
  // A stretch [begin, end) of positions in the pixel sequence.
  struct PixelRun {
    std::uint64_t begin = 0, end = 0;
  };
  // Called with a run's number before the first of its records reach the
  // sink (from the thread calling the sink), once per run, in order.
  using RunStart = std::function<void(std::size_t run)>;

  // Keeps references to all three; they must outlive the renderer.
  Renderer(const Scene& scene, const AccelerationStructure& accel, const Layout& layout,
           const RenderOptions& options);
  Renderer(const Scene& scene, const KdTree& tree, const Layout& layout,
           const RenderOptions& options);

  // Renders every pixel. Records reach `sink` in the sequential order (pixel
  // by pixel, each pixel's ray tree depth-first) whatever the thread count,
  // or, with more than one ray in flight or unit, in the order of
  // render_in_flight. `image` (optional) receives the picture.
  RenderStats render(const RecordCallback& sink, Image* image, const Progress& progress = {}) const;
  // Renders every pixel with the units and rays in flight of the options:
  // each pixel's rays are traced on the workers, each ray's records kept
  // apart, then RayScheduler interleaves them in order, so the records do
  // not depend on the thread count. With one unit of one slot, the records
  // of render().
  RenderStats render_in_flight(const RecordCallback& sink, Image* image, const Progress& progress = {}) const;
  // An empty image of the options' size; with path tracing it has a
  // variance plane and is linear radiance.
  void prepare_image(Image& image) const;
  // Renders the pixels of `runs` only (in increasing, disjoint order), the
  // others' rays never traced; their records are those the full render
  // makes for these pixels, in the same order.
  RenderStats render_runs(std::span<const PixelRun> runs, const RunStart& run_start, const RecordCallback& sink,
                          Image* image, const Progress& progress = {}) const;

  // A ray the render cast, and its kind.
  struct CastRay {
    RayKind kind = RayKind::Primary;
    Ray ray;
  };
  // Every ray the render casts for positions [begin, end) of the pixel
  // sequence, in the order cast, traced on this thread with nothing
  // recorded: the same rays render() casts there (benchmarks of traversal
  // by ray kind).
  std::vector<CastRay> cast_rays(std::uint64_t begin, std::uint64_t end) const;

  // One traversal each, appending its records to `records` when not null;
  // the acceleration structure's traversal does the work.
  std::optional<Hit> closest_hit(const Ray& ray, float t_max, std::vector<formats::Record>* records,
                                 RenderStats* stats) const;
  bool occluded(const Ray& ray, float t_max, std::vector<formats::Record>* records,
                RenderStats* stats) const;

  const RayKindPlan& ray_plan() const { return plan_; }
  const Camera& camera() const { return camera_; }

 private:
  struct Context;
  Renderer(const Scene& scene, const Bounds& bounds, std::unique_ptr<RayTraversal> traversal,
           const RenderOptions& options);
  struct ShadingPoint;
  ShadingPoint shading_point(const Ray& ray, const Hit& hit) const;
  // Casts the shadow ray from `origin` to the light (a child of ray
  // `caster`): whether nothing blocks it.
  bool light_visible(const Vec3& origin, const PointLight& light, std::uint32_t caster, Context& context) const;
  // The same for a point `target` (on an area light).
  bool point_visible(const Vec3& origin, const Vec3& target, std::uint32_t caster, Context& context) const;
  // The same for the environment in `direction`: nothing in the way, however far.
  bool direction_visible(const Vec3& origin, const Vec3& direction, std::uint32_t caster, Context& context) const;
  // Casts, counts, times and records a shadow ray over [0, t_max) of `shadow`.
  bool shadow_ray_clear(const Ray& shadow, float t_max, std::uint32_t caster, Context& context) const;
  // A cast ray: its id (the caster of its shadow rays, the parent of its
  // children) and its closest hit.
  struct TracedRay {
    std::uint32_t id;
    std::optional<Hit> hit;
  };
  // Casts `ray` of `kind` (a child of context.parent), counted, timed and
  // recorded. Both integrators' rays other than shadow rays.
  TracedRay cast_closest(const Ray& ray, RayKind kind, Context& context) const;
  Vec3 shade(const Ray& ray, RayKind kind, int depth, Context& context) const;
  // One path: the radiance of one sample of the pixel (path_tracer.cpp).
  Vec3 trace_path(std::uint32_t pixel, std::uint32_t sample, Context& context) const;
  // Both integrators: the pixel's samples (Whitted: one), their mean and
  // (path tracing) sample variance into the image.
  void render_pixel(std::uint32_t pixel, Context& context, Image* image) const;

  const Scene& scene_;
  RenderOptions options_;
  RayKindPlan plan_;
  Camera camera_;
  PinholeCamera pinhole_;
  std::unique_ptr<RayTraversal> traversal_;
  std::vector<Vec3> face_normals_;  // unit geometric normals
  std::size_t lights_shadowed_ = 0;  // the first this many lights get shadow rays
  float light_scale_ = 1;
  std::shared_ptr<const detail::Emitters> emitters_;  // the emissive triangles (path tracing)
};

}  // namespace nodetrace::tracer
