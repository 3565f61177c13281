// primary_rays_bench: primary rays per second of the tracer's kd-tree
// traversal (no trace recorded) against Embree's rtcIntersect1 on the same
// rays and triangles, one thread each, for scripts/bench-tracer.sh. Embree is
// a benchmark-only reference: this program is built only where
// libembree-dev is installed, and nothing else links it.
//   primary_rays_bench SCENE [--width W] [--height H] [--runs N]
// Prints one line of key=value figures: medians of N runs (default 3).
#include <embree3/rtcore.h>

#include <algorithm>
#include <chrono>
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
#include "nodetrace/tracer/scene/scene_loader.hpp"

namespace {

using namespace nodetrace::tracer;
using Clock = std::chrono::steady_clock;

constexpr std::uint32_t kNoHit = std::numeric_limits<std::uint32_t>::max();

double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  return values[values.size() / 2];
}

// The triangle each ray hits first (kNoHit for none), and the seconds taken.
template <typename Trace>
double time_rays(const std::vector<Ray>& rays, std::vector<std::uint32_t>& hits, Trace trace) {
  const auto start = Clock::now();
  for (std::size_t i = 0; i < rays.size(); ++i) hits[i] = trace(rays[i]);
  return std::chrono::duration<double>(Clock::now() - start).count();
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

 private:
  RTCDevice device_ = nullptr;
  RTCScene scene_ = nullptr;
};

int run(int argc, char** argv) {
  std::string spec;
  int width = 400, height = 300, runs = 3;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if ((arg == "--width" || arg == "--height" || arg == "--runs") && i + 1 < argc) {
      const int value = std::stoi(argv[++i]);
      if (value < 1) throw nodetrace::base::UsageError(arg + ": expected a positive number");
      (arg == "--width" ? width : arg == "--height" ? height : runs) = value;
    } else if (spec.empty() && arg[0] != '-') {
      spec = arg;
    } else {
      throw nodetrace::base::UsageError("usage: primary_rays_bench SCENE [--width W] [--height H] [--runs N]");
    }
  }
  if (spec.empty()) throw nodetrace::base::UsageError("usage: primary_rays_bench SCENE [--width W] [--height H] [--runs N]");

  const auto source = open_scene(spec);
  const Scene scene = source->at_frame(0);
  const PinholeCamera camera(scene.camera.value_or(default_camera(scene.bounds())), width, height);
  std::vector<Ray> rays;
  rays.reserve(static_cast<std::size_t>(width) * height);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) rays.push_back(camera.primary_ray(x, y));
  }

  const KdTree tree = KdTree::build(scene.triangles);
  const Layout layout = make_layout(tree, LayoutKind::Dfl);
  StreamSelection no_streams;
  no_streams.nodes = false;
  const Traversal traversal(scene.triangles, tree, layout, no_streams, AddressMap{});
  const EmbreeScene embree(scene.triangles);

  std::vector<std::uint32_t> ours(rays.size()), theirs(rays.size());
  std::vector<double> our_seconds, their_seconds;
  for (int r = 0; r < runs; ++r) {
    our_seconds.push_back(time_rays(rays, ours, [&](const Ray& ray) {
      Hit hit;
      return traversal.closest_hit(ray, std::numeric_limits<float>::infinity(), hit, nullptr, nullptr)
                 ? hit.triangle
                 : kNoHit;
    }));
    their_seconds.push_back(time_rays(rays, theirs, [&](const Ray& ray) { return embree.closest(ray); }));
  }
  std::size_t same = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) same += ours[i] == theirs[i];
  const double our_rate = static_cast<double>(rays.size()) / median(our_seconds);
  const double their_rate = static_cast<double>(rays.size()) / median(their_seconds);
  std::printf("scene=%s rays=%zu triangles=%zu runs=%d kdtree_rays_per_s=%.0f embree_rays_per_s=%.0f "
              "ratio=%.3f same_first_hit=%zu\n",
              source->name().c_str(), rays.size(), scene.triangles.size(), runs, our_rate, their_rate,
              our_rate / their_rate, same);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return nodetrace::cli::exit_status_of("primary_rays_bench", [&] { return run(argc, argv); });
}
