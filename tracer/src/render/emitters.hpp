// The scene's emissive triangles as area lights for next-event estimation:
// one is chosen with probability proportional to its power (area times the
// mean of its emitted radiance), then a point uniformly on it. Emission is
// two-sided (as Cycles' mesh lights are): a triangle emits its material's
// radiance from both faces. Internal header of the path tracer.
#pragma once

#include <cstdint>
#include <vector>

#include "nodetrace/tracer/geometry/vec3.hpp"
#include "nodetrace/tracer/scene/scene.hpp"

namespace nodetrace::tracer::detail {

// A material's emitted radiance, or 0 for one that does not emit.
bool emits(const Material& material);

class Emitters {
 public:
  explicit Emitters(const Scene& scene);

  bool empty() const { return triangles_.empty(); }

  struct Sample {
    Vec3 point;
    Vec3 normal;        // unit geometric normal (either side emits)
    Vec3 radiance;      // emitted radiance
    float pdf_area = 0; // probability density per unit area of the point
  };
  // A point on an emitter from two uniform numbers in [0, 1): `u` chooses
  // the emitter and, rescaled to its share, with `v` the point on it, so a
  // stratified (u, v) pair stays stratified over all the emitters' area.
  Sample sample(float u, float v) const;
  // The density per unit area with which sample() picks a point of
  // `triangle` (0 for a triangle that does not emit).
  float pdf_area(std::uint32_t triangle) const;

 private:
  const Scene& scene_;
  std::vector<std::uint32_t> triangles_;  // emissive, in scene order
  std::vector<double> cdf_;               // running power sum, parallel to triangles_
  std::vector<float> pdf_area_;           // per scene triangle: choice probability / area
};

}  // namespace nodetrace::tracer::detail
