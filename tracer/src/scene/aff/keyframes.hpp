// Kochanek-Bartels keyframe splines of BART AFF (`k` blocks): Hermite
// interpolation of translation and scale keys, squad of rotation keys, with
// tension / continuity / bias tangents corrected for uneven key spacing; and
// the animated transform they make together. Internal to the AFF loader.
#pragma once

#include <array>
#include <optional>
#include <utility>
#include <vector>

#include "scene/aff/affine.hpp"
#include "scene/aff/quaternion.hpp"

namespace nodetrace::tracer::detail::aff {

struct Key {
  double time = 0;
  std::array<double, 4> value{};
  double tension = 0, continuity = 0, bias = 0;
};

// Position or scale track: Hermite interpolation with KB tangents. `keys`
// non-empty, in time order.
std::array<double, 3> evaluate_vector(const std::vector<Key>& keys, double time);

// Rotation track: keys are axis-angle; interpolated as quaternions with squad
// and KB tangents taken in the logarithm space.
class RotationTrack {
 public:
  explicit RotationTrack(std::vector<Key> keys);
  Quat at(double time) const;

 private:
  std::vector<Key> keys_;
  std::vector<Quat> quats_, outgoing_control_, incoming_control_;
};

// Translation, then rotation, then scale, each track optional.
struct AnimatedTransform {
  std::vector<Key> translation, scale;
  std::optional<RotationTrack> rotation;
  Affine at(double time) const;
};

}  // namespace nodetrace::tracer::detail::aff
