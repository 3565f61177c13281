#include "nodetrace/tracer/render/camera.hpp"

#include <cmath>

#include "nodetrace/base/portable_math.hpp"
#include "nodetrace/tracer/render/interaction.hpp"

namespace nodetrace::tracer {

// The same results on every machine (portable_math.hpp).
namespace math = base::portable_math;

Camera default_camera(const Bounds& bounds) {
  Camera camera;
  if (bounds.empty()) return camera;
  const Vec3 center = (bounds.lo + bounds.hi) * 0.5f;
  const float half_diagonal = length(bounds.hi - bounds.lo) * 0.5f;
  const float radius = half_diagonal > 0 ? half_diagonal : 1e-6f;  // a single point: any small distance
  camera.fov_y_degrees = 45;
  const float distance = radius / math::sin(camera.fov_y_degrees * 0.5f * 3.14159265f / 180.0f);
  camera.eye = center + normalize(Vec3{0.35f, 0.3f, 1.0f}) * distance;
  camera.look_at = center;
  camera.up = {0, 1, 0};
  return camera;
}

PinholeCamera::PinholeCamera(const Camera& camera, int width, int height)
    : eye_(camera.eye), width_(float(width)), height_(float(height)) {
  forward_ = unit_vector(camera.look_at - camera.eye);
  Vec3 right = cross(forward_, camera.up);
  // An up along the view: any direction across it will do.
  if (length(right) == 0) right = cross(forward_, std::fabs(forward_.y) < 0.9f ? Vec3{0, 1, 0} : Vec3{1, 0, 0});
  right_ = normalize(right);
  up_ = cross(right_, forward_);
  half_height_ = math::tan(camera.fov_y_degrees * 0.5f * 3.14159265f / 180.0f);
  half_width_ = half_height_ * width_ / height_;
}

Ray PinholeCamera::primary_ray(int x, int y) const { return ray_through(float(x) + 0.5f, float(y) + 0.5f); }

Ray PinholeCamera::ray_through(float px, float py) const {
  const float sx = (px / width_ * 2.0f - 1.0f) * half_width_;
  const float sy = (1.0f - py / height_ * 2.0f) * half_height_;
  return {eye_, normalize(forward_ + right_ * sx + up_ * sy)};
}

}  // namespace nodetrace::tracer
