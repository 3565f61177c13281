#include "nodetrace/tracer/scene/scene.hpp"

namespace nodetrace::tracer {

Bounds Scene::bounds() const {
  Bounds box;
  for (const auto& triangle : triangles) {
    box.extend(triangle.v0);
    box.extend(triangle.v1);
    box.extend(triangle.v2);
  }
  return box;
}

double Animation::time_of_frame(std::uint64_t frame) const {
  if (frames <= 1) return start;
  return start + static_cast<double>(frame) * (end - start) / static_cast<double>(frames - 1);
}

}  // namespace nodetrace::tracer
