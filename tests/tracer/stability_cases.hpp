// The numerical-stability cases (issue 9), shared by the GoogleTest suite
// (small sizes) and the stability_table program that scripts/stability.sh
// runs at scale. Each case is a scene with a camera; a probe walks every
// pixel's ray tree (every surface taken as a mirror, plus a shadow ray per
// light) through the library's own intersection, hit-point and offset
// functions and counts what must never happen.
#pragma once

#include <sys/resource.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "nodetrace/tracer/render/interaction.hpp"
#include "nodetrace/tracer/accel/kdtree.hpp"
#include "nodetrace/tracer/accel/layout.hpp"
#include "nodetrace/tracer/render/render.hpp"
#include "nodetrace/tracer/scene/scene.hpp"
#include "nodetrace/tracer/scene/scene_geometry.hpp"
#include "test_render_scenes.hpp"

namespace nodetrace::tracer::stability {

struct Case {
  std::string name;
  Scene scene;
  Camera camera;
  int width = 32, height = 24;
  int max_depth = 3;          // mirror bounces + 1
  bool closed = false;        // camera inside a closed mesh: every ray must hit
  bool fan_rays = false;      // also shoot rays exactly through the fan's shared edges and vertices
  bool fills_view = false;    // every primary ray must hit something
};

struct Counts {
  std::uint64_t triangles = 0;
  double build_seconds = 0;      // wall
  double build_cpu_seconds = 0;  // user + sys of the process during the build
  std::uint64_t rays = 0;
  std::uint64_t self_hits = 0;         // a spawned ray meeting the surface it left
  std::uint64_t escapes = 0;           // a ray from inside a closed mesh meeting nothing
  std::uint64_t watertight_misses = 0; // a ray through a shared edge or vertex not hit exactly once
  std::uint64_t nans = 0;              // a non-finite t, barycentric, point, bound or ray
  std::uint64_t primary_misses = 0;    // primary rays meeting nothing
};

inline Scene with_one_material(Scene scene) {
  if (scene.materials.empty()) scene.materials.push_back({});
  return scene;
}

inline Camera camera(Vec3 eye, Vec3 look_at, Vec3 up = {0, 1, 0}, float fov = 60) {
  return Camera{eye, look_at, up, fov};
}

inline Scene scaled(Scene scene, int power) {
  const float s = std::ldexp(1.0f, power);
  for (auto& t : scene.triangles) t.v0 = t.v0 * s, t.v1 = t.v1 * s, t.v2 = t.v2 * s;
  for (auto& l : scene.lights) l.position = l.position * s;
  return scene;
}

// A small closed world within |x| <= 2 (so 2^60 times it stays in range):
// a floor, a sphere and a box, two lights.
inline Scene scale_scene() {
  Scene scene = with_one_material({});
  scene.name = "scale";
  test_scenes::add_quad(scene, {-2, -1, -2}, {-2, -1, 2}, {2, -1, 2}, {2, -1, -2}, 0);
  for (const auto& t : make_sphere_mesh({-0.5f, -0.25f, 0.25f}, 0.75f, 2)) scene.triangles.push_back(t);
  test_scenes::add_box(scene, {0.5f, -1, -1}, {1.5f, 0.25f, 0}, 0);
  scene.lights.push_back({{1.5f, 1.75f, 1.5f}, {1, 1, 1}});
  scene.lights.push_back({{-1.75f, 1.5f, -0.5f}, {0.5f, 0.5f, 0.5f}});
  return scene;
}

inline Case scale_case(int power, int pixels) {
  Case c;
  c.name = "scale 2^" + std::to_string(power);
  c.scene = scaled(scale_scene(), power);
  const float s = std::ldexp(1.0f, power);
  c.camera = camera(Vec3{0.5f, 0.75f, 1.75f} * s, Vec3{0, -0.5f, 0} * s);
  c.width = pixels, c.height = pixels * 3 / 4;
  return c;
}

// `count` small triangles scattered over [-extent, extent]^2 at height
// `height`, size `size`: the clutter on the big floors.
inline void add_clutter(Scene& scene, std::size_t count, float extent, float size, float height,
                        std::uint32_t seed) {
  std::mt19937 engine(seed);
  for (std::size_t i = 0; i < count; ++i) {
    const Vec3 c{test_scenes::uniform(engine, -extent, extent), height,
                 test_scenes::uniform(engine, -extent, extent)};
    scene.triangles.push_back({c, c + Vec3{size, 0, 0}, c + Vec3{0, size, size}, 0});
  }
}

// A floor 2e7 wide at y = 0 of two triangles, clutter, 500 zero-area
// triangles are left to the loaders; camera `eye_height` above it.
inline Case big_floor_case(float eye_height, int pixels) {
  Case c;
  c.name = "floor 2e7, camera at " + std::to_string(static_cast<long long>(eye_height));
  c.scene = with_one_material({});
  test_scenes::add_quad(c.scene, {-1e7f, 0, -1e7f}, {-1e7f, 0, 1e7f}, {1e7f, 0, 1e7f}, {1e7f, 0, -1e7f}, 0);
  add_clutter(c.scene, 2000, 2e6f, 2e4f, 1e4f, 7);
  c.scene.triangles.push_back({{-1e6f, 1, 0}, {1e6f, 1, 0}, {0, 1.0000001f, 1e-7f}, 0});  // a sliver
  c.scene.lights.push_back({{3e6f, 8e6f, 2e6f}, {1, 1, 1}});
  c.camera = camera({0, eye_height, eye_height}, {0, 0, 0});
  c.width = pixels, c.height = pixels * 3 / 4;
  c.fills_view = true;
  return c;
}

// A plane 2e7 wide tilted about two axes, seen from near its centre.
inline Case tilted_plane_case(int pixels) {
  Case c;
  c.name = "tilted plane 2e7";
  c.scene = with_one_material({});
  const Vec3 u = unit_vector({1, 0.3f, 0.1f}), v = unit_vector(cross({0.2f, 1, -0.4f}, u));
  const Vec3 o{1234.5f, -987.25f, 4321.75f};
  const float h = 1e7f;
  test_scenes::add_quad(c.scene, o - u * h - v * h, o + u * h - v * h, o + u * h + v * h, o - u * h + v * h, 0);
  const Vec3 n = unit_vector(cross(u, v));
  c.scene.lights.push_back({o + n * 5e5f + u * 1e5f, {1, 1, 1}});
  // 10 units above the plane, looking 63 degrees down: the view is all plane.
  c.camera = camera(o + n * 10.0f + u * 3.0f, o + u * 8.0f + v * 0.5f, n);
  c.width = pixels, c.height = pixels * 3 / 4;
  c.fills_view = true;
  return c;
}

// The camera inside a closed icosphere whose inside is a mirror: every
// primary and every bounce must hit it, none its own triangle.
inline Case inside_closed_mesh_case(int subdivisions, int pixels) {
  Case c;
  c.name = "camera inside closed mesh";
  c.scene = with_one_material({});
  c.scene.triangles = make_sphere_mesh({0.3f, -0.1f, 0.2f}, 3, subdivisions);
  c.scene.lights.push_back({{0.5f, 0.5f, 0.5f}, {1, 1, 1}});
  c.camera = camera({0.1f, 0.2f, 0.3f}, {1.1f, -0.3f, -0.9f});
  c.width = pixels, c.height = pixels * 3 / 4;
  c.max_depth = 6;
  c.closed = true;
  c.fills_view = true;
  return c;
}

// A closed fan of eight triangles around the origin in z = 0 whose spokes
// lie on the axes and diagonals, so points exactly on shared edges are
// representable; the camera looks exactly along -z.
inline Case fan_case(int pixels) {
  Case c;
  c.name = "axis rays through fan edges and vertices";
  c.scene = with_one_material({});
  const Vec3 rim[8] = {{8, 0, 0}, {8, 8, 0}, {0, 8, 0}, {-8, 8, 0}, {-8, 0, 0}, {-8, -8, 0}, {0, -8, 0}, {8, -8, 0}};
  for (int i = 0; i < 8; ++i) c.scene.triangles.push_back({{0, 0, 0}, rim[i], rim[(i + 1) % 8], 0});
  c.scene.lights.push_back({{1, 2, 5}, {1, 1, 1}});
  c.camera = camera({0, 0, 5}, {0, 0, 0});
  c.width = pixels, c.height = pixels;
  c.fan_rays = true;
  c.fills_view = true;
  return c;
}

// Rays meeting a wide floor at 1e-7 rad.
inline Case grazing_case(int pixels) {
  Case c;
  c.name = "grazing rays at 1e-7 rad";
  c.scene = with_one_material({});
  test_scenes::add_quad(c.scene, {-1e3f, 0, -1e9f}, {-1e3f, 0, 1e9f}, {1e3f, 0, 1e9f}, {1e3f, 0, -1e9f}, 0);
  c.scene.lights.push_back({{0, 100, 0}, {1, 1, 1}});
  // Eye 1 unit up, looking 1e-7 rad down: hits about 1e7 away.
  c.camera = camera({0, 1, 0}, {0, 1 - 1e-7f * 1e3f, -1e3f});
  c.camera.fov_y_degrees = 1e-5f;  // every pixel within ~1e-7 rad of the axis
  c.width = pixels, c.height = pixels * 3 / 4;
  c.fills_view = true;
  return c;
}

// Random overlapping triangles all in the plane z = 0 (the flat kd-tree build).
inline Case coplanar_case(std::size_t count, int pixels) {
  Case c;
  c.name = "coplanar overlapping triangles";
  c.scene = with_one_material({});
  std::mt19937 engine(11);
  for (std::size_t i = 0; i < count; ++i) {
    Triangle t;
    for (Vec3* v : {&t.v0, &t.v1, &t.v2}) *v = {test_scenes::uniform(engine, 0, 1), test_scenes::uniform(engine, 0, 1), 0};
    c.scene.triangles.push_back(t);
  }
  c.scene.lights.push_back({{0.3f, 0.6f, 2}, {1, 1, 1}});
  c.camera = camera({0.5f, 0.5f, 1.5f}, {0.5f, 0.5f, 0});
  c.width = pixels, c.height = pixels * 3 / 4;
  c.max_depth = 2;
  return c;
}

// Slivers 1e-3 high at most, all sharing the edge (0,0,0)-(1,0,0), in z = 0.
inline Case sliver_case(std::size_t count, int pixels) {
  Case c;
  c.name = "slivers sharing one edge";
  c.scene = with_one_material({});
  std::mt19937 engine(12);
  for (std::size_t i = 0; i < count; ++i) {
    c.scene.triangles.push_back({{0, 0, 0}, {1, 0, 0},
                                 {test_scenes::uniform(engine, 0, 1), test_scenes::uniform(engine, 1e-7f, 1e-3f), 0}, 0});
  }
  c.scene.lights.push_back({{0.5f, 0.5f, 2}, {1, 1, 1}});
  c.camera = camera({0.5f, 0.0005f, 0.002f}, {0.5f, 0.0005f, 0});
  c.width = pixels, c.height = pixels * 3 / 4;
  c.max_depth = 2;
  return c;
}

// Triangles whose sizes and positions span 1e-30 to 1e30.
inline Case range_case(std::size_t count, int pixels) {
  Case c;
  c.name = "sizes from 1e-30 to 1e30";
  c.scene = with_one_material({});
  std::mt19937 engine(13);
  for (std::size_t i = 0; i < count; ++i) {
    const float s = std::pow(10.0f, test_scenes::uniform(engine, -30, 30));
    const Vec3 m{test_scenes::uniform(engine, -1, 1) * s, test_scenes::uniform(engine, -1, 1) * s,
                 test_scenes::uniform(engine, -1, 1) * s};
    Triangle t;
    for (Vec3* v : {&t.v0, &t.v1, &t.v2}) {
      *v = m + Vec3{test_scenes::uniform(engine, -1, 1), test_scenes::uniform(engine, -1, 1),
                    test_scenes::uniform(engine, -1, 1)} * (0.1f * s);
    }
    c.scene.triangles.push_back(t);
  }
  c.scene.lights.push_back({{1e29f, 2e29f, 3e29f}, {1, 1, 1}});
  c.camera = camera({0, 0, 4e29f}, {0, 0, 0});
  c.width = pixels, c.height = pixels * 3 / 4;
  c.max_depth = 2;
  return c;
}

// The same triangle `count` times (planar splits keep all of them on both sides).
inline Case coincident_case(std::size_t count, int pixels) {
  Case c;
  c.name = "coincident triangles";
  c.scene = with_one_material({});
  c.scene.triangles.assign(count, Triangle{{0, 0, 0}, {1, 0, 0.25f}, {0.25f, 1, 0.5f}, 0});
  c.scene.lights.push_back({{0.5f, 0.5f, 3}, {1, 1, 1}});
  c.camera = camera({0.4f, 0.4f, 2}, {0.4f, 0.4f, 0});
  c.width = pixels, c.height = pixels * 3 / 4;
  c.max_depth = 2;
  return c;
}

// Small 3-D triangles scattered in a cube: the reference for build costs.
inline Case soup_case(std::size_t count, int pixels) {
  Case c;
  c.name = "3-D soup (reference)";
  c.scene = with_one_material(test_scenes::random_triangles(count, 14, 10.0f, 0.5f));
  c.scene.lights.push_back({{20, 30, 40}, {1, 1, 1}});
  c.camera = camera({0, 0, 35}, {0, 0, 0});
  c.width = pixels, c.height = pixels * 3 / 4;
  c.max_depth = 2;
  return c;
}

// Two facing mirrors with the camera between them, looking almost along
// their normal: every bounce hits, up to max_depth 64.
inline Case hall_of_mirrors_case(int pixels) {
  Case c;
  c.name = "hall of mirrors, depth 64";
  c.scene = with_one_material({});
  test_scenes::add_quad(c.scene, {-50, -50, -1}, {50, -50, -1}, {50, 50, -1}, {-50, 50, -1}, 0);
  test_scenes::add_quad(c.scene, {-50, -50, 1}, {-50, 50, 1}, {50, 50, 1}, {50, -50, 1}, 0);
  c.scene.lights.push_back({{0.1f, 0.2f, 0.3f}, {1, 1, 1}});
  c.camera = camera({0, 0, 0}, {0.01f, 0.005f, -1});
  c.camera.fov_y_degrees = 2;
  c.width = pixels, c.height = pixels * 3 / 4;
  c.max_depth = 64;
  c.fills_view = true;
  return c;
}

namespace detail {

inline bool finite(const Vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

struct Probe {
  const Case& c;
  const Renderer& renderer;
  Counts& counts;

  static constexpr float kInf = std::numeric_limits<float>::infinity();

  // A ray that starts on triangle `source` at `start` met something that is
  // the surface it left: the same triangle, or any hit within the start's
  // own error box (a coplanar neighbour).
  bool is_self_hit(std::uint32_t source, const SurfacePoint& start, const Hit& hit, const Ray& ray) const {
    if (hit.triangle == source) return true;
    const Vec3 at = ray.origin + ray.direction * hit.t;
    const Vec3 d = at - start.point;
    const float reach = 4 * std::max({start.error.x, start.error.y, start.error.z});
    return std::fabs(d.x) <= reach && std::fabs(d.y) <= reach && std::fabs(d.z) <= reach;
  }

  void walk(const Ray& ray, int depth, bool inside) {
    ++counts.rays;
    if (!finite(ray.origin) || !finite(ray.direction)) {
      ++counts.nans;
      return;
    }
    const auto hit = renderer.closest_hit(ray, kInf, nullptr, nullptr);
    if (!hit) {
      if (inside) ++counts.escapes;
      if (depth == 1) ++counts.primary_misses;
      return;
    }
    const Triangle& t = c.scene.triangles[hit->triangle];
    const SurfacePoint surface = interpolate_surface_point(t, hit->b0, hit->u, hit->v);
    if (!std::isfinite(hit->t) || !std::isfinite(hit->b0) || !std::isfinite(hit->u) ||
        !std::isfinite(hit->v) || !finite(surface.point) || !finite(surface.error)) {
      ++counts.nans;
      return;
    }
    Vec3 facing = triangle_unit_normal(t, {0, 0, 1});
    if (dot(facing, ray.direction) > 0) facing = -facing;
    const Vec3 origin = offset_ray_origin(surface, facing);
    for (const auto& light : c.scene.lights) {
      if (dot(light.position - surface.point, facing) <= 0) continue;
      const Ray shadow{origin, light.position - origin};
      ++counts.rays;
      if (const auto blocker = renderer.closest_hit(shadow, 1.0f - 1e-4f, nullptr, nullptr)) {
        if (is_self_hit(hit->triangle, surface, *blocker, shadow)) ++counts.self_hits;
      }
    }
    if (depth >= c.max_depth) return;
    const Vec3 direction = ray.direction - facing * (2 * dot(ray.direction, facing));
    const Ray bounce{origin, unit_vector(direction)};
    if (const auto next = renderer.closest_hit(bounce, kInf, nullptr, nullptr)) {
      if (is_self_hit(hit->triangle, surface, *next, bounce)) {
        ++counts.rays;
        ++counts.self_hits;
        return;
      }
    }
    walk(bounce, depth + 1, inside);
  }
};

}  // namespace detail

// The primary ray of pixel (x, y), as the renderer makes it.
inline Ray primary_ray(const Camera& camera, int x, int y, int width, int height) {
  const Vec3 forward = unit_vector(camera.look_at - camera.eye);
  const Vec3 right = unit_vector(cross(forward, camera.up));
  const Vec3 up = cross(right, forward);
  const float half_height = std::tan(camera.fov_y_degrees * 0.5f * 3.14159265f / 180.0f);
  const float half_width = half_height * float(width) / float(height);
  const float sx = ((float(x) + 0.5f) / float(width) * 2.0f - 1.0f) * half_width;
  const float sy = (1.0f - (float(y) + 0.5f) / float(height) * 2.0f) * half_height;
  return {camera.eye, unit_vector(forward + right * sx + up * sy)};
}

inline double process_cpu_seconds() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return double(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
         1e-6 * double(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
}

inline Counts run(const Case& c) {
  Counts counts;
  counts.triangles = c.scene.triangles.size();
  const auto start = std::chrono::steady_clock::now();
  const double cpu_start = process_cpu_seconds();
  const KdTree tree = KdTree::build(c.scene.triangles);
  counts.build_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  counts.build_cpu_seconds = process_cpu_seconds() - cpu_start;
  const Layout layout = make_layout(tree, LayoutKind::Dfl);
  RenderOptions options;
  options.camera = c.camera;
  const Renderer renderer(c.scene, tree, layout, options);
  detail::Probe probe{c, renderer, counts};
  for (int y = 0; y < c.height; ++y) {
    for (int x = 0; x < c.width; ++x) probe.walk(primary_ray(c.camera, x, y, c.width, c.height), 1, c.closed);
  }
  if (c.fan_rays) {
    // Through the centre vertex and through points on the spokes (axes and
    // diagonals: exact in float), counted over every triangle of the fan:
    // each must be hit exactly once.
    std::vector<Vec3> targets{{0, 0, 0}};
    for (float r : {0.5f, 1.0f, 2.25f, 3.0f, 6.5f}) {
      targets.insert(targets.end(), {{r, 0, 0}, {-r, 0, 0}, {0, r, 0}, {0, -r, 0}, {r, r, 0}, {-r, r, 0},
                                     {r, -r, 0}, {-r, -r, 0}});
    }
    for (const Vec3& p : targets) {
      // Along the axis both ways, and obliquely (then the ray passes the
      // point within rounding: still exactly one triangle must own it).
      for (const Vec3& d : {Vec3{0, 0, -1}, Vec3{0, 0, 1}, unit_vector({0.3f, -0.2f, -1}), unit_vector({-1, 1, 0.5f})}) {
        const Ray ray{p - d * 5.0f, d};
        int hits = 0;
        for (const auto& t : c.scene.triangles) hits += intersect_triangle(ray, t, detail::Probe::kInf).has_value();
        ++counts.rays;
        if (hits != 1) ++counts.watertight_misses;
        if (!renderer.closest_hit(ray, detail::Probe::kInf, nullptr, nullptr)) ++counts.watertight_misses;
      }
    }
  }
  return counts;
}

}  // namespace nodetrace::tracer::stability
