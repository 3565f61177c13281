// Built-in procedural scenes, so the tracer works with no scene files:
// a sphereflake, a fractal mountain with a lake, and a forest of recursive
// trees (our stand-in for the Fairy Forest). Deterministic: every random
// number comes from a fixed-seed splitmix64, never from <random>'s
// implementation-defined distributions.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <initializer_list>
#include <mutex>
#include <numbers>
#include <string>
#include <vector>

#include "nodetrace/base/portable_math.hpp"
#include "nodetrace/tracer/scene/scene_geometry.hpp"
#include "scene/scene_internal.hpp"

namespace nodetrace::tracer {

// The same results on every machine (portable_math.hpp).
namespace math = base::portable_math;

namespace detail {

namespace {

class SplitMix64 {
 public:
  explicit SplitMix64(std::uint64_t seed) : state_(seed) {}
  std::uint64_t next() {
    std::uint64_t z = (state_ += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }
  // Uniform in [0, 1) from the top 53 bits.
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }

 private:
  std::uint64_t state_;
};

Material make_material(const char* name, Vec3 diffuse, Vec3 specular, float shininess, float reflectance,
                       float transmittance = 0, float ior = 1) {
  Material m;
  m.name = name;
  m.diffuse = diffuse;
  m.specular = specular;
  m.shininess = shininess;
  m.reflectance = reflectance;
  m.transmittance = transmittance;
  m.ior = ior;
  return m;
}

std::uint32_t add_material(Scene& scene, Material material) {
  scene.materials.push_back(std::move(material));
  return static_cast<std::uint32_t>(scene.materials.size() - 1);
}

void append(Scene& scene, const std::vector<Triangle>& triangles) {
  scene.triangles.insert(scene.triangles.end(), triangles.begin(), triangles.end());
}

// Axis-aligned horizontal rectangle at height y, facing up.
void add_quad(Scene& scene, float x0, float z0, float x1, float z1, float y, std::uint32_t material) {
  const Vec3 a{x0, y, z0}, b{x1, y, z0}, c{x1, y, z1}, d{x0, y, z1};
  scene.triangles.push_back({a, d, c, material});
  scene.triangles.push_back({a, c, b, material});
}

// Any unit vector perpendicular to `axis`.
Vec3 perpendicular(const Vec3& axis) {
  const Vec3 helper = std::fabs(axis.x) < 0.9f ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
  return normalize(cross(axis, helper));
}

// ---------------------------------------------------------------- sphereflake

// Fewer triangles for smaller spheres: finest for the two largest levels.
int sphereflake_subdivisions(int level) { return std::max(0, 3 - std::max(0, level - 1)); }

void add_sphereflake(Scene& scene, const Vec3& center, float radius, const Vec3& axis, int level, int depth,
                     std::uint32_t material) {
  append(scene, make_sphere_mesh(center, radius, sphereflake_subdivisions(level), material));
  if (level == depth) return;
  // Nine children: six around the equator, three at 60 degrees towards `axis`.
  const Vec3 u = perpendicular(axis);
  const Vec3 v = cross(axis, u);
  const float child_radius = radius / 3;
  for (int i = 0; i < 9; ++i) {
    const bool equator = i < 6;
    const double azimuth = equator ? i * std::numbers::pi / 3 : (2 * (i - 6) + 0.5) * std::numbers::pi / 3;
    const double elevation = equator ? 0.0 : std::numbers::pi / 3;
    const Vec3 direction = normalize(u * static_cast<float>(math::cos(azimuth) * math::cos(elevation)) +
                                     v * static_cast<float>(math::sin(azimuth) * math::cos(elevation)) +
                                     axis * static_cast<float>(math::sin(elevation)));
    add_sphereflake(scene, center + direction * (radius + child_radius), child_radius, direction, level + 1,
                    depth, material);
  }
}

Scene sphereflake(int depth) {
  Scene scene;
  const auto floor = add_material(scene, make_material("floor", {0.55f, 0.6f, 0.7f}, {0.2f, 0.2f, 0.2f}, 20, 0.15f));
  const auto mirror = add_material(scene, make_material("mirror", {0.25f, 0.2f, 0.15f}, {0.9f, 0.9f, 0.9f}, 80, 0.7f));
  const auto glass = add_material(scene, make_material("glass", {0.05f, 0.05f, 0.05f}, {1, 1, 1}, 120, 0.1f, 0.9f, 1.5f));
  add_quad(scene, -8, -8, 8, 8, 0, floor);
  add_sphereflake(scene, {0, 1, 0}, 1, {0, 1, 0}, 0, depth, mirror);
  for (const Vec3& c : {Vec3{2.4f, 0.4f, 0.3f}, Vec3{-2.3f, 0.4f, 0.9f}, Vec3{1.1f, 0.4f, 2.3f}}) {
    append(scene, make_sphere_mesh(c, 0.4f, 3, glass));
  }
  scene.lights = {{{6, 9, 7}, {0.7f, 0.7f, 0.65f}}, {{-7, 6, 3}, {0.35f, 0.35f, 0.45f}}, {{1, 8, -6}, {0.3f, 0.3f, 0.3f}}};
  scene.camera = Camera{{3.4f, 2.7f, 4.6f}, {0, 1.05f, 0}, {0, 1, 0}, 42};
  scene.background = {0.35f, 0.45f, 0.6f};
  return scene;
}

// ---------------------------------------------------------------- mountain

Scene mountain(int exponent) {
  Scene scene;
  const auto rock = add_material(scene, make_material("rock", {0.45f, 0.4f, 0.32f}, {0.1f, 0.1f, 0.1f}, 10, 0));
  const auto grass = add_material(scene, make_material("grass", {0.25f, 0.45f, 0.18f}, {0, 0, 0}, 0, 0));
  const auto snow = add_material(scene, make_material("snow", {0.9f, 0.9f, 0.95f}, {0.3f, 0.3f, 0.3f}, 30, 0));
  const auto lake = add_material(scene, make_material("lake", {0.05f, 0.1f, 0.15f}, {0.8f, 0.8f, 0.8f}, 100, 0.75f));
  const auto glass = add_material(scene, make_material("glass", {0.05f, 0.05f, 0.05f}, {1, 1, 1}, 120, 0.1f, 0.9f, 1.5f));

  // Diamond-square midpoint displacement on a (2^n + 1)^2 height grid.
  const int cells = 1 << exponent, side = cells + 1;
  std::vector<double> height(static_cast<std::size_t>(side) * side, 0.0);
  auto h = [&](int x, int z) -> double& { return height[static_cast<std::size_t>(z) * side + x]; };
  SplitMix64 random(0x6d6f756e7461696eULL);  // "mountain"
  h(0, 0) = 0.5, h(cells, 0) = 1.0, h(0, cells) = 0.8, h(cells, cells) = 2.5;
  double amplitude = 4.0;
  for (int step = cells; step > 1; step /= 2, amplitude *= 0.52) {
    const int half = step / 2;
    for (int z = half; z < cells; z += step) {
      for (int x = half; x < cells; x += step) {
        h(x, z) = (h(x - half, z - half) + h(x + half, z - half) + h(x - half, z + half) + h(x + half, z + half)) / 4 +
                  random.uniform(-amplitude, amplitude);
      }
    }
    for (int z = 0; z <= cells; z += half) {
      for (int x = (z / half) % 2 == 0 ? half : 0; x <= cells; x += step) {
        double sum = 0;
        int count = 0;
        for (const auto& [dx, dz] : {std::pair{-half, 0}, std::pair{half, 0}, std::pair{0, -half}, std::pair{0, half}}) {
          if (x + dx >= 0 && x + dx <= cells && z + dz >= 0 && z + dz <= cells) sum += h(x + dx, z + dz), ++count;
        }
        h(x, z) = sum / count + random.uniform(-amplitude, amplitude);
      }
    }
  }
  // A basin in the middle for the lake; mountains rise towards the back.
  const float extent = 10;
  auto point = [&](int x, int z) {
    const double fx = static_cast<double>(x) / cells * 2 - 1, fz = static_cast<double>(z) / cells * 2 - 1;
    const double basin = 2.0 * math::exp(-3.0 * (fx * fx + (fz - 0.1) * (fz - 0.1)));
    const double ridge = 2.0 * std::max(0.0, -fz);
    return Vec3{static_cast<float>(fx * extent), static_cast<float>(h(x, z) * 0.6 - basin + ridge),
                static_cast<float>(fz * extent)};
  };
  std::vector<double> sorted;
  sorted.reserve(height.size());
  for (int z = 0; z <= cells; ++z) {
    for (int x = 0; x <= cells; ++x) sorted.push_back(point(x, z).y);
  }
  std::sort(sorted.begin(), sorted.end());
  const float water = static_cast<float>(sorted[sorted.size() * 3 / 10]);
  const float snow_line = static_cast<float>(sorted[sorted.size() * 88 / 100]);
  const float grass_line = static_cast<float>(sorted[sorted.size() * 60 / 100]);
  for (int z = 0; z < cells; ++z) {
    for (int x = 0; x < cells; ++x) {
      const Vec3 a = point(x, z), b = point(x + 1, z), c = point(x + 1, z + 1), d = point(x, z + 1);
      for (const auto& [p, q, r] : {std::array{a, d, c}, std::array{a, c, b}}) {
        const float top = std::max({p.y, q.y, r.y});
        const auto material = top > snow_line ? snow : top > grass_line ? rock : grass;
        scene.triangles.push_back({p, q, r, material});
      }
    }
  }
  add_quad(scene, -extent, -extent, extent, extent, water, lake);
  append(scene, make_sphere_mesh({1.5f, water + 1.6f, 3.0f}, 1.1f, 3, glass));
  scene.lights = {{{30, 40, 25}, {0.8f, 0.75f, 0.65f}}, {{-25, 20, 20}, {0.3f, 0.35f, 0.45f}}};
  scene.camera = Camera{{0, water + 7.5f, 17}, {0, water + 0.5f, -1}, {0, 1, 0}, 50};
  scene.background = {0.55f, 0.7f, 0.9f};
  return scene;
}

// ---------------------------------------------------------------- forest

struct TreeMaterials {
  std::uint32_t bark, leaves;
};

void add_branch(Scene& scene, SplitMix64& random, const Vec3& base, const Vec3& direction, float length,
                float radius, int level, int depth, const TreeMaterials& materials) {
  const Vec3 tip = base + direction * length;
  append(scene, make_cone_mesh(base, radius, tip, radius * 0.7f, 8, materials.bark));
  if (level == depth) {
    append(scene, make_sphere_mesh(tip, length * 0.6f, 0, materials.leaves));
    return;
  }
  const Vec3 u = perpendicular(direction);
  const Vec3 v = cross(direction, u);
  const double spin = random.uniform(0, 2 * std::numbers::pi);
  for (int i = 0; i < 3; ++i) {
    const double azimuth = spin + i * 2 * std::numbers::pi / 3 + random.uniform(-0.3, 0.3);
    const double tilt = random.uniform(0.45, 0.8);
    const Vec3 sideways = u * static_cast<float>(math::cos(azimuth)) + v * static_cast<float>(math::sin(azimuth));
    Vec3 child = direction * static_cast<float>(math::cos(tilt)) + sideways * static_cast<float>(math::sin(tilt));
    child = normalize(child + Vec3{0, 0.15f, 0});  // branches reach for the light
    add_branch(scene, random, tip, child, length * static_cast<float>(random.uniform(0.62, 0.78)), radius * 0.7f,
               level + 1, depth, materials);
  }
}

Scene forest(int trees_per_side) {
  Scene scene;
  const auto ground = add_material(scene, make_material("ground", {0.35f, 0.3f, 0.2f}, {0, 0, 0}, 0, 0));
  const TreeMaterials materials{
      add_material(scene, make_material("bark", {0.35f, 0.22f, 0.12f}, {0.05f, 0.05f, 0.05f}, 5, 0)),
      add_material(scene, make_material("leaves", {0.2f, 0.5f, 0.15f}, {0.2f, 0.2f, 0.2f}, 20, 0))};
  const auto pond = add_material(scene, make_material("pond", {0.05f, 0.08f, 0.1f}, {0.9f, 0.9f, 0.9f}, 120, 0.8f));
  const auto glass = add_material(scene, make_material("glass", {0.05f, 0.05f, 0.05f}, {1, 1, 1}, 120, 0.1f, 0.9f, 1.5f));

  const float spacing = 4.5f;
  const float half_width = spacing * trees_per_side / 2;
  add_quad(scene, -half_width - 6, -half_width - 6, half_width + 6, half_width + 10, 0, ground);
  add_quad(scene, -3.5f, half_width + 0.8f, 3.5f, half_width + 5.5f, 0.01f, pond);
  SplitMix64 random(0x666f72657374ULL);  // "forest"
  for (int row = 0; row < trees_per_side; ++row) {
    for (int column = 0; column < trees_per_side; ++column) {
      const Vec3 base{-half_width + spacing * (column + 0.5f) + static_cast<float>(random.uniform(-0.8, 0.8)), 0,
                      -half_width + spacing * (row + 0.5f) + static_cast<float>(random.uniform(-0.8, 0.8))};
      const float size = static_cast<float>(random.uniform(0.85, 1.15));
      add_branch(scene, random, base, {0, 1, 0}, 1.6f * size, 0.18f * size, 0, 5, materials);
    }
  }
  for (const Vec3& c : {Vec3{-1.8f, 0.55f, half_width + 3.0f}, Vec3{1.6f, 0.55f, half_width + 2.2f}}) {
    append(scene, make_sphere_mesh(c, 0.55f, 3, glass));
  }
  const float distance = half_width + 14;
  scene.lights = {{{distance, 2 * distance, distance}, {0.75f, 0.72f, 0.6f}},
                  {{-distance, distance, distance * 0.5f}, {0.3f, 0.3f, 0.4f}},
                  {{0, 6, half_width + 8}, {0.25f, 0.25f, 0.25f}}};
  scene.camera = Camera{{0, 3.5f + half_width * 0.45f, half_width + 12}, {0, 2.2f, 0}, {0, 1, 0}, 50};
  scene.background = {0.6f, 0.75f, 0.95f};
  return scene;
}

// ---------------------------------------------------------------- registry

struct Generator {
  const char* name;
  const char* description;
  int default_size, min_size, max_size;
  Scene (*make)(int size);
};

constexpr std::array<Generator, 3> kGenerators{{
    {"sphereflake", "recursive mirror sphereflake on a floor with three glass spheres; size = recursion depth", 3,
     1, 4, sphereflake},
    {"mountain", "midpoint-displacement terrain with a mirror lake and a glass sphere; size = log2 of the grid side",
     7, 6, 8, mountain},
    {"forest", "recursive trees around a mirror pond with glass spheres; size = trees per side of the grid", 3, 1, 5,
     forest},
}};

// Smooth vertex normals: each corner averages the (area-weighted) normals of
// the triangles sharing its exact position whose facing is within 60 degrees
// of its own, so spheres, leaves and terrain shade round while creases stay
// sharp.
void add_smooth_normals(Scene& scene) {
  const std::size_t count = scene.triangles.size();
  std::vector<Vec3> face(count);
  // Corners sorted by the bits of their position: equal positions are adjacent.
  struct Corner {
    std::array<std::uint32_t, 3> bits;
    std::uint32_t index;  // 3 * triangle + corner
  };
  std::vector<Corner> corners(3 * count);
  for (std::size_t i = 0; i < count; ++i) {
    const Triangle& t = scene.triangles[i];
    face[i] = cross(t.v1 - t.v0, t.v2 - t.v0);  // length = twice the area
    int k = 0;
    for (const Vec3* v : {&t.v0, &t.v1, &t.v2}) {
      Corner& c = corners[3 * i + k];
      std::memcpy(c.bits.data(), v, sizeof c.bits);
      c.index = static_cast<std::uint32_t>(3 * i + k++);
    }
  }
  std::sort(corners.begin(), corners.end(),
            [](const Corner& a, const Corner& b) { return a.bits != b.bits ? a.bits < b.bits : a.index < b.index; });
  const float crease_cosine = 0.5f;
  scene.vertex_normals.resize(3 * count);
  for (std::size_t begin = 0; begin < corners.size();) {
    std::size_t end = begin + 1;
    while (end < corners.size() && corners[end].bits == corners[begin].bits) ++end;
    for (std::size_t a = begin; a < end; ++a) {
      const Vec3& own_face = face[corners[a].index / 3];
      const float own_length = length(own_face);
      const Vec3 own = own_length > 0 ? own_face / own_length : Vec3{0, 1, 0};
      Vec3 sum{0, 0, 0};
      for (std::size_t b = begin; b < end; ++b) {
        const Vec3& other = face[corners[b].index / 3];
        const float other_length = length(other);
        if (other_length > 0 && dot(other, own) >= crease_cosine * other_length) sum += other;
      }
      const float sum_length = length(sum);
      scene.vertex_normals[corners[a].index] = sum_length > 0 ? sum / sum_length : own;
    }
    begin = end;
  }
}

Scene generate(const Generator& generator, int size, bool with_normals = true) {
  Scene scene = generator.make(size);
  if (with_normals) add_smooth_normals(scene);
  scene.name = generator.name;
  scene.ambient = {0.12f, 0.12f, 0.12f};
  return scene;
}

// Name, size and everything generated, so a change to a generator changes
// the hash recorded in trace headers.
std::uint64_t content_hash(const Scene& scene, int size) {
  std::uint64_t hash = fnv1a64("nodetrace-builtin:" + scene.name + ":" + std::to_string(size));
  auto feed_floats = [&](std::initializer_list<float> values) {
    for (const float value : values) {
      hash = fnv1a64(std::string_view(reinterpret_cast<const char*>(&value), sizeof value), hash);
    }
  };
  for (const auto& t : scene.triangles) {
    feed_floats({t.v0.x, t.v0.y, t.v0.z, t.v1.x, t.v1.y, t.v1.z, t.v2.x, t.v2.y, t.v2.z,
                 static_cast<float>(t.material)});
  }
  for (const auto& m : scene.materials) {
    feed_floats({m.diffuse.x, m.diffuse.y, m.diffuse.z, m.specular.x, m.specular.y, m.specular.z, m.shininess,
                 m.reflectance, m.transmittance, m.ior});
  }
  for (const auto& light : scene.lights) {
    feed_floats({light.position.x, light.position.y, light.position.z, light.color.x, light.color.y, light.color.z});
  }
  if (scene.camera) {
    const Camera& c = *scene.camera;
    feed_floats({c.eye.x, c.eye.y, c.eye.z, c.look_at.x, c.look_at.y, c.look_at.z, c.up.x, c.up.y, c.up.z,
                 c.fov_y_degrees});
  }
  feed_floats({scene.background.x, scene.background.y, scene.background.z, scene.ambient.x, scene.ambient.y,
               scene.ambient.z});
  return hash;
}

}  // namespace

std::unique_ptr<SceneSource> open_builtin(const std::string& name, std::optional<int> requested) {
  for (const auto& generator : kGenerators) {
    if (name != generator.name) continue;
    const int size = requested.value_or(generator.default_size);
    if (size < generator.min_size || size > generator.max_size) {
      throw SceneError("scene '" + name + ":" + std::to_string(size) + "': size " + std::to_string(size) +
                       " is out of range " + std::to_string(generator.min_size) + ".." +
                       std::to_string(generator.max_size));
    }
    Scene scene = generate(generator, size);
    std::string hash = format_hash(content_hash(scene, size));
    return std::make_unique<StaticSceneSource>(std::move(scene), std::move(hash));
  }
  throw SceneError("no built-in scene named '" + name + "'");
}

bool is_builtin_name(const std::string& name) {
  return std::any_of(kGenerators.begin(), kGenerators.end(),
                     [&](const Generator& generator) { return name == generator.name; });
}

std::string builtin_names() {
  std::string names;
  for (const auto& generator : kGenerators) names += (names.empty() ? "" : ", ") + std::string(generator.name);
  return names;
}

}  // namespace detail

std::vector<BuiltinSceneInfo> builtin_scenes() {
  // Counts come from generating the scenes once (a few milliseconds each).
  static std::once_flag once;
  static std::vector<BuiltinSceneInfo> infos;
  std::call_once(once, [] {
    for (const auto& generator : detail::kGenerators) {
      BuiltinSceneInfo info{generator.name, generator.description, generator.default_size, 0, generator.min_size,
                            generator.max_size};
      info.triangles = detail::generate(generator, generator.default_size, false).triangles.size();
      info.min_triangles = detail::generate(generator, generator.min_size, false).triangles.size();
      info.max_triangles = detail::generate(generator, generator.max_size, false).triangles.size();
      infos.push_back(std::move(info));
    }
  });
  return infos;
}

std::string default_scene_name() { return "sphereflake"; }

}  // namespace nodetrace::tracer
