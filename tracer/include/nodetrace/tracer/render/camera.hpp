// The pinhole camera: where the primary ray of each pixel goes, and the
// framing used when neither the scene nor the user gives a camera.
#pragma once

#include "nodetrace/tracer/geometry/ray.hpp"
#include "nodetrace/tracer/scene/scene.hpp"

namespace nodetrace::tracer {

// A camera that frames `bounds` from the front, slightly above and right.
Camera default_camera(const Bounds& bounds);

// A camera's view of an image of width x height pixels: one primary ray
// through the centre of each pixel, row 0 at the top.
class PinholeCamera {
 public:
  PinholeCamera(const Camera& camera, int width, int height);
  Ray primary_ray(int x, int y) const;

 private:
  Vec3 eye_, forward_, right_, up_;
  float half_width_ = 0, half_height_ = 0;
  float width_ = 1, height_ = 1;
};

}  // namespace nodetrace::tracer
