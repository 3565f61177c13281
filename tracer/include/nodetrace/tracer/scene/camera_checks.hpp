// Whether a camera can frame a view at all, checked where a camera is read
// (a scene's `v` block, the --eye/--look-at/--up options) so a degenerate one
// is an error there instead of rays with NaN directions.
#pragma once

#include <cmath>

#include "nodetrace/tracer/scene/scene.hpp"

namespace nodetrace::tracer {

enum class CameraProblem { None, EyeAtLookAt, UpAlongView };

inline CameraProblem camera_problem(const Vec3& eye, const Vec3& look_at, const Vec3& up) {
  const double dx = double(look_at.x) - eye.x, dy = double(look_at.y) - eye.y, dz = double(look_at.z) - eye.z;
  const double view = std::sqrt(dx * dx + dy * dy + dz * dz);
  if (!(view > 0)) return CameraProblem::EyeAtLookAt;
  const double ux = up.x, uy = up.y, uz = up.z;
  const double up_length = std::sqrt(ux * ux + uy * uy + uz * uz);
  const double cx = dy * uz - dz * uy, cy = dz * ux - dx * uz, cz = dx * uy - dy * ux;
  // The sine of the angle between up and the view: below 1e-6 no image
  // plane orientation follows from them.
  if (!(std::sqrt(cx * cx + cy * cy + cz * cz) > 1e-6 * view * up_length)) return CameraProblem::UpAlongView;
  return CameraProblem::None;
}

}  // namespace nodetrace::tracer
