// The pinhole camera: where the primary ray of each pixel goes, and the
// framing used when neither the scene nor the user gives a camera.
#pragma once

#include "nodetrace/tracer/geometry/ray.hpp"
#include "nodetrace/tracer/scene/scene.hpp"

namespace nodetrace::tracer {

// A camera that frames `bounds` from the front, slightly above and right.
Camera default_camera(const Bounds& bounds);

// A camera's view of an image of width x height pixels: the primary ray
// through the centre of each pixel (or any point of it), row 0 at the top.
class PinholeCamera {
 public:
  PinholeCamera(const Camera& camera, int width, int height);
  Ray primary_ray(int x, int y) const;
  // The ray through image position (px, py): pixel (x, y) covers
  // [x, x + 1) x [y, y + 1), so primary_ray(x, y) is ray_through(x + 0.5, y + 0.5).
  Ray ray_through(float px, float py) const;

 private:
  Vec3 eye_, forward_, right_, up_;
  float half_width_ = 0, half_height_ = 0;
  float width_ = 1, height_ = 1;
};

}  // namespace nodetrace::tracer
