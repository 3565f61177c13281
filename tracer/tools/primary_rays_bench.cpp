// primary_rays_bench: primary rays per second of the tracer's kd-tree
// traversal (no trace recorded) against Embree's rtcIntersect1 on the same
// rays and triangles, one thread each, for scripts/bench-tracer.sh. Embree is
// a benchmark-only reference: this program is built only where
// libembree-dev is installed, and nothing else links it. With --path SPP the
// rays are a path tracer's (Renderer::cast_rays, --integrator path --spp
// SPP), timed kind by kind: shadow rays as any-hit queries (rtcOccluded1),
// the others as closest-hit queries.
//   primary_rays_bench SCENE [--width W] [--height H] [--runs N] [--path SPP]
// Prints one line of key=value figures per ray kind (rays per CPU second of
// this thread, so other processes on the core do not count): medians of N
// runs (default 3), and what our traversal does per ray (node fetches,
// leaves, triangle tests).
#include <embree3/rtcore.h>

#include <algorithm>
#include <ctime>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "nodetrace/base/error.hpp"
#include "nodetrace/cli/exit_status.hpp"
#include "nodetrace/tracer/accel/kdtree.hpp"
#include "nodetrace/tracer/accel/layout.hpp"
#include "nodetrace/tracer/accel/traversal.hpp"
#include "nodetrace/tracer/render/camera.hpp"
#include "nodetrace/tracer/render/render.hpp"
#include "nodetrace/tracer/scene/scene_loader.hpp"

namespace {

using namespace nodetrace::tracer;

constexpr std::uint32_t kNoHit = std::numeric_limits<std::uint32_t>::max();

double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  return values[values.size() / 2];
}

// This thread's CPU time: on a machine shared with other work, wall time
// would count the time other processes held the core.
double thread_cpu_seconds() {
  timespec now{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
  return double(now.tv_sec) + double(now.tv_nsec) * 1e-9;
}

// The triangle each ray hits first (kNoHit for none), and the CPU seconds taken.
template <typename Trace>
double time_rays(const std::vector<Ray>& rays, std::vector<std::uint32_t>& hits, Trace trace) {
  const double start = thread_cpu_seconds();
  for (std::size_t i = 0; i < rays.size(); ++i) hits[i] = trace(rays[i]);
  return thread_cpu_seconds() - start;
}

class EmbreeScene {
 public:
  explicit EmbreeScene(const std::vector<Triangle>& triangles) {
    device_ = rtcNewDevice("threads=1");
    if (device_ == nullptr) throw std::runtime_error("Embree: cannot create a device");
    scene_ = rtcNewScene(device_);
    RTCGeometry geometry = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), 3 * triangles.size()));
    auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), triangles.size()));
    for (std::size_t i = 0; i < triangles.size(); ++i) {
      const Vec3* corners[3] = {&triangles[i].v0, &triangles[i].v1, &triangles[i].v2};
      for (int k = 0; k < 3; ++k) {
        vertices[9 * i + 3 * k] = corners[k]->x;
        vertices[9 * i + 3 * k + 1] = corners[k]->y;
        vertices[9 * i + 3 * k + 2] = corners[k]->z;
        indices[3 * i + k] = static_cast<unsigned>(3 * i + k);
      }
    }
    rtcCommitGeometry(geometry);
    rtcAttachGeometry(scene_, geometry);
    rtcReleaseGeometry(geometry);
    rtcCommitScene(scene_);
  }
  ~EmbreeScene() {
    rtcReleaseScene(scene_);
    rtcReleaseDevice(device_);
  }
  EmbreeScene(const EmbreeScene&) = delete;
  EmbreeScene& operator=(const EmbreeScene&) = delete;

  std::uint32_t closest(const Ray& ray) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit query{};
    query.ray.org_x = ray.origin.x;
    query.ray.org_y = ray.origin.y;
    query.ray.org_z = ray.origin.z;
    query.ray.dir_x = ray.direction.x;
    query.ray.dir_y = ray.direction.y;
    query.ray.dir_z = ray.direction.z;
    query.ray.tnear = 0;
    query.ray.tfar = std::numeric_limits<float>::infinity();
    query.ray.mask = ~0u;
    query.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(scene_, &context, &query);
    return query.hit.geomID == RTC_INVALID_GEOMETRY_ID ? kNoHit : query.hit.primID;
  }

  // 1 when something lies on the ray before t_max (the direction's length
  // is the unit of t), else 0.
  std::uint32_t occluded(const Ray& ray, float t_max) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRay query{};
    query.org_x = ray.origin.x;
    query.org_y = ray.origin.y;
    query.org_z = ray.origin.z;
    query.dir_x = ray.direction.x;
    query.dir_y = ray.direction.y;
    query.dir_z = ray.direction.z;
    query.tnear = 0;
    query.tfar = t_max;
    query.mask = ~0u;
    rtcOccluded1(scene_, &context, &query);
    return query.tfar < 0 ? 1 : 0;  // Embree sets tfar to -inf on a hit
  }

 private:
  RTCDevice device_ = nullptr;
  RTCScene scene_ = nullptr;
};

// The shadow rays' t_max, as the renderer casts them (shading.cpp).
constexpr float kShadowReach = 1.0f - 1e-4f;

int run(int argc, char** argv) {
  const char* usage = "usage: primary_rays_bench SCENE [--width W] [--height H] [--runs N] [--path SPP]";
  std::string spec;
  int width = 400, height = 300, runs = 3, path_spp = 0;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if ((arg == "--width" || arg == "--height" || arg == "--runs" || arg == "--path") && i + 1 < argc) {
      const int value = std::stoi(argv[++i]);
      if (value < 1) throw nodetrace::base::UsageError(arg + ": expected a positive number");
      (arg == "--width" ? width : arg == "--height" ? height : arg == "--runs" ? runs : path_spp) = value;
    } else if (spec.empty() && arg[0] != '-') {
      spec = arg;
    } else {
      throw nodetrace::base::UsageError(usage);
    }
  }
  if (spec.empty()) throw nodetrace::base::UsageError(usage);

  const auto source = open_scene(spec);
  const Scene scene = source->at_frame(0);
  const KdTree tree = KdTree::build(scene.triangles);
  const Layout layout = make_layout(tree, LayoutKind::Dfl);
  StreamSelection no_streams;
  no_streams.nodes = false;
  const Traversal traversal(scene.triangles, tree, layout, no_streams, AddressMap{});
  const EmbreeScene embree(scene.triangles);

  // The rays of each kind: the primary rays, or a path tracer's.
  std::vector<std::vector<Ray>> rays(kRayKindCount);
  if (path_spp == 0) {
    const PinholeCamera camera(scene.camera.value_or(default_camera(scene.bounds())), width, height);
    for (int y = 0; y < height; ++y) {
      for (int x = 0; x < width; ++x) rays[0].push_back(camera.primary_ray(x, y));
    }
  } else {
    RenderOptions options;
    options.integrator = Integrator::Path;
    options.path.samples_per_pixel = static_cast<std::uint32_t>(path_spp);
    options.width = width;
    options.height = height;
    options.record = false;
    const Renderer renderer(scene, tree, layout, options);
    for (const auto& cast : renderer.cast_rays(0, std::uint64_t(width) * std::uint64_t(height))) {
      rays[static_cast<int>(cast.kind)].push_back(cast.ray);
    }
  }

  for (int k = 0; k < kRayKindCount; ++k) {
    const std::vector<Ray>& kind_rays = rays[k];
    if (kind_rays.empty()) continue;
    const bool shadow = static_cast<RayKind>(k) == RayKind::Shadow;
    std::vector<std::uint32_t> ours(kind_rays.size()), theirs(kind_rays.size());
    std::vector<double> our_seconds, their_seconds;
    for (int r = 0; r < runs; ++r) {
      our_seconds.push_back(time_rays(kind_rays, ours, [&](const Ray& ray) -> std::uint32_t {
        if (shadow) return traversal.any_hit(ray, kShadowReach, nullptr, nullptr) ? 1 : 0;
        Hit hit;
        return traversal.closest_hit(ray, std::numeric_limits<float>::infinity(), hit, nullptr, nullptr)
                   ? hit.triangle
                   : kNoHit;
      }));
      their_seconds.push_back(time_rays(kind_rays, theirs, [&](const Ray& ray) {
        return shadow ? embree.occluded(ray, kShadowReach) : embree.closest(ray);
      }));
    }
    std::size_t same = 0;
    for (std::size_t i = 0; i < kind_rays.size(); ++i) same += ours[i] == theirs[i];
    // What our rays do on average (one untimed pass): where the time goes.
    RenderStats work;
    for (const Ray& ray : kind_rays) {
      Hit hit;
      if (shadow) {
        traversal.any_hit(ray, kShadowReach, nullptr, &work);
      } else {
        traversal.closest_hit(ray, std::numeric_limits<float>::infinity(), hit, nullptr, &work);
      }
    }
    const double count = static_cast<double>(kind_rays.size());
    const double our_rate = static_cast<double>(kind_rays.size()) / median(our_seconds);
    const double their_rate = static_cast<double>(kind_rays.size()) / median(their_seconds);
    std::printf("scene=%s kind=%s rays=%zu triangles=%zu runs=%d kdtree_rays_per_s=%.0f embree_rays_per_s=%.0f "
                "ratio=%.3f same_%s=%zu nodes_per_ray=%.1f leaves_per_ray=%.1f tests_per_ray=%.1f\n",
                source->name().c_str(), std::string(ray_kind_name(static_cast<RayKind>(k))).c_str(),
                kind_rays.size(), scene.triangles.size(), runs, our_rate, their_rate, our_rate / their_rate,
                shadow ? "answer" : "first_hit", same, double(work.node_fetches) / count,
                double(work.leaf_visits) / count, double(work.triangle_tests) / count);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return nodetrace::cli::exit_status_of("primary_rays_bench", [&] { return run(argc, argv); });
}
