// A ray, what it hits, and the ray/triangle test every traversal uses.
#pragma once

#include <cstdint>
#include <optional>

#include "nodetrace/tracer/scene/scene.hpp"
#include "nodetrace/tracer/geometry/vec3.hpp"

namespace nodetrace::tracer {

struct Ray {
  Vec3 origin, direction;
};

struct Hit {
  float t = 0;
  std::uint32_t triangle = 0;
  float u = 0, v = 0;  // barycentrics of v1 and v2
  float b0 = 0;        // barycentric of v0, from its own edge function (not 1 - u - v)
};

// Watertight ray/triangle test (Woop, Benthin and Wald 2013): hits with
// 0 < t < t_max, where t is also beyond its own rounding error. A ray exactly
// through an edge shared by two triangles hits exactly one of them, and one
// through the shared vertex of a closed fan exactly one of the fan. New rays
// start at offset_ray_origin (interaction.hpp).
std::optional<Hit> intersect_triangle(const Ray& ray, const Triangle& triangle, float t_max);

}  // namespace nodetrace::tracer
