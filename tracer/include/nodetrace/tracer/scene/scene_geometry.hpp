// Geometry helpers shared by the scene loaders and useful to tests: closed
// tessellated primitives.
#pragma once

#include <cstdint>
#include <vector>

#include "nodetrace/tracer/scene/scene.hpp"

namespace nodetrace::tracer {

// A closed, consistently wound (outward-facing, counter-clockwise seen from
// outside) icosphere: 20 * 4^subdivisions triangles, every vertex exactly on
// the sphere. Shared edges use bit-identical vertices, so the mesh is
// watertight. All triangles get `material`.
std::vector<Triangle> make_sphere_mesh(const Vec3& center, float radius, int subdivisions,
                                       std::uint32_t material = 0);

// An open cone or cylinder frustum (NFF `c`): `sides` quads split in two,
// from a circle of `base_radius` at `base` to one of `apex_radius` at `apex`.
std::vector<Triangle> make_cone_mesh(const Vec3& base, float base_radius, const Vec3& apex,
                                     float apex_radius, int sides, std::uint32_t material = 0);

}  // namespace nodetrace::tracer
