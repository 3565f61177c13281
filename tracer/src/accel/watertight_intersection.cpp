#include "accel/watertight_intersection.hpp"

namespace nodetrace::tracer {

std::optional<Hit> intersect_triangle(const Ray& ray, const Triangle& triangle, float t_max) {
  Hit hit;
  if (detail::intersect_sheared(detail::ShearedRay(ray), triangle, t_max, hit)) return hit;
  return std::nullopt;
}

}  // namespace nodetrace::tracer
