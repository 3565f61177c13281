#include "nodetrace/tracer/scene/scene_geometry.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numbers>
#include <utility>

#include "nodetrace/base/portable_math.hpp"

namespace nodetrace::tracer {

// The same results on every machine (portable_math.hpp).
namespace math = base::portable_math;

namespace {

struct DVec {
  double x, y, z;
};

DVec normalized(DVec v) {
  const double len = std::sqrt(v.x * v.x + v.y * v.y + v.z * v.z);
  return {v.x / len, v.y / len, v.z / len};
}

}  // namespace

std::vector<Triangle> make_sphere_mesh(const Vec3& center, float radius, int subdivisions,
                                       std::uint32_t material) {
  // Unit icosahedron; subdividing at edge midpoints cached per edge keeps
  // shared vertices bit-identical.
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<DVec> vertices = {{-1, t, 0}, {1, t, 0},   {-1, -t, 0}, {1, -t, 0},
                                {0, -1, t}, {0, 1, t},   {0, -1, -t}, {0, 1, -t},
                                {t, 0, -1}, {t, 0, 1},   {-t, 0, -1}, {-t, 0, 1}};
  for (auto& v : vertices) v = normalized(v);
  std::vector<std::array<int, 3>> faces = {
      {0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
      {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
      {3, 8, 9},  {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (int level = 0; level < subdivisions; ++level) {
    std::map<std::pair<int, int>, int> midpoints;
    auto midpoint = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      const auto found = midpoints.find(key);
      if (found != midpoints.end()) return found->second;
      const DVec& p = vertices[key.first];
      const DVec& q = vertices[key.second];
      vertices.push_back(normalized({(p.x + q.x) / 2, (p.y + q.y) / 2, (p.z + q.z) / 2}));
      const int index = static_cast<int>(vertices.size() - 1);
      midpoints.emplace(key, index);
      return index;
    };
    std::vector<std::array<int, 3>> finer;
    finer.reserve(faces.size() * 4);
    for (const auto& f : faces) {
      const int ab = midpoint(f[0], f[1]), bc = midpoint(f[1], f[2]), ca = midpoint(f[2], f[0]);
      finer.push_back({f[0], ab, ca});
      finer.push_back({f[1], bc, ab});
      finer.push_back({f[2], ca, bc});
      finer.push_back({ab, bc, ca});
    }
    faces = std::move(finer);
  }
  std::vector<Vec3> placed;
  placed.reserve(vertices.size());
  for (const auto& v : vertices) {
    placed.emplace_back(static_cast<float>(center.x + v.x * radius),
                        static_cast<float>(center.y + v.y * radius),
                        static_cast<float>(center.z + v.z * radius));
  }
  std::vector<Triangle> triangles;
  triangles.reserve(faces.size());
  for (const auto& f : faces) triangles.push_back({placed[f[0]], placed[f[1]], placed[f[2]], material});
  return triangles;
}

std::vector<Triangle> make_cone_mesh(const Vec3& base, float base_radius, const Vec3& apex,
                                     float apex_radius, int sides, std::uint32_t material) {
  std::vector<Triangle> triangles;
  if (sides < 3) sides = 3;
  const Vec3 axis_vector = apex - base;
  const float axis_length = length(axis_vector);
  if (!(axis_length > 0)) return triangles;
  const Vec3 axis = axis_vector / axis_length;
  // Any vector not parallel to the axis gives the circle's frame.
  const Vec3 helper = std::fabs(axis.x) < 0.9f ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
  const Vec3 u = normalize(cross(axis, helper));
  const Vec3 v = cross(axis, u);
  std::vector<Vec3> bottom(sides), top(sides);
  for (int i = 0; i < sides; ++i) {
    const double angle = 2.0 * std::numbers::pi * i / sides;
    const Vec3 direction = u * static_cast<float>(math::cos(angle)) + v * static_cast<float>(math::sin(angle));
    bottom[i] = base + direction * base_radius;
    top[i] = apex + direction * apex_radius;
  }
  for (int i = 0; i < sides; ++i) {
    const int j = (i + 1) % sides;
    if (base_radius > 0) triangles.push_back({bottom[i], bottom[j], top[j], material});
    if (apex_radius > 0) triangles.push_back({bottom[i], top[j], top[i], material});
  }
  return triangles;
}

}  // namespace nodetrace::tracer
