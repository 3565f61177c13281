#include "scene/aff/keyframes.hpp"

#include <algorithm>

namespace nodetrace::tracer::detail::aff {

namespace {

// Outgoing (source) and incoming (destination) tangent weights of key k for
// the differences to its previous and next key, with the usual correction for
// unevenly spaced keys.
struct TangentWeights {
  double out_prev, out_next, in_prev, in_next;
};

TangentWeights tangent_weights(const std::vector<Key>& keys, std::size_t k) {
  const Key& key = keys[k];
  const double t = key.tension, c = key.continuity, b = key.bias;
  TangentWeights w{(1 - t) * (1 + c) * (1 + b) / 2, (1 - t) * (1 - c) * (1 - b) / 2,
                   (1 - t) * (1 - c) * (1 + b) / 2, (1 - t) * (1 + c) * (1 - b) / 2};
  const std::size_t n = keys.size();
  if (k > 0 && k + 1 < n) {
    const double before = keys[k].time - keys[k - 1].time, after = keys[k + 1].time - keys[k].time;
    if (before + after > 0) {
      const double out_scale = 2 * after / (before + after), in_scale = 2 * before / (before + after);
      w.out_prev *= out_scale, w.out_next *= out_scale;
      w.in_prev *= in_scale, w.in_next *= in_scale;
    }
  }
  return w;
}

// Index i with keys[i].time <= time < keys[i + 1].time, and the fraction u.
std::pair<std::size_t, double> locate(const std::vector<Key>& keys, double time) {
  const auto after = std::upper_bound(keys.begin(), keys.end(), time,
                                      [](double t, const Key& key) { return t < key.time; });
  const std::size_t i = static_cast<std::size_t>(after - keys.begin()) - 1;
  const double span = keys[i + 1].time - keys[i].time;
  return {i, (time - keys[i].time) / span};
}

}  // namespace

// Position or scale track: Hermite interpolation with KB tangents.
std::array<double, 3> evaluate_vector(const std::vector<Key>& keys, double time) {
  auto value = [&](std::size_t k) { return std::array<double, 3>{keys[k].value[0], keys[k].value[1], keys[k].value[2]}; };
  if (keys.size() == 1 || time <= keys.front().time) return value(0);
  if (time >= keys.back().time) return value(keys.size() - 1);
  const auto [i, u] = locate(keys, time);
  const std::size_t n = keys.size();
  auto differences = [&](std::size_t k, int axis) {
    const double next = k + 1 < n ? keys[k + 1].value[axis] - keys[k].value[axis] : 0;
    const double prev = k > 0 ? keys[k].value[axis] - keys[k - 1].value[axis] : next;
    return std::pair<double, double>{prev, k + 1 < n ? next : prev};
  };
  const TangentWeights w0 = tangent_weights(keys, i), w1 = tangent_weights(keys, i + 1);
  const double u2 = u * u, u3 = u2 * u;
  const double h00 = 2 * u3 - 3 * u2 + 1, h10 = u3 - 2 * u2 + u, h01 = -2 * u3 + 3 * u2, h11 = u3 - u2;
  std::array<double, 3> result{};
  for (int axis = 0; axis < 3; ++axis) {
    const auto [prev0, next0] = differences(i, axis);
    const auto [prev1, next1] = differences(i + 1, axis);
    const double outgoing = w0.out_prev * prev0 + w0.out_next * next0;
    const double incoming = w1.in_prev * prev1 + w1.in_next * next1;
    result[axis] = h00 * keys[i].value[axis] + h10 * outgoing + h01 * keys[i + 1].value[axis] + h11 * incoming;
  }
  return result;
}

RotationTrack::RotationTrack(std::vector<Key> keys) : keys_(std::move(keys)) {
  for (const Key& key : keys_) {
    Quat q = from_axis_angle(key.value[0], key.value[1], key.value[2], key.value[3]);
    // Keep neighbours in one hemisphere so each segment takes the short way.
    if (!quats_.empty() && dot(quats_.back(), q) < 0) q = {-q.w, -q.x, -q.y, -q.z};
    quats_.push_back(q);
  }
  const std::size_t n = quats_.size();
  for (std::size_t k = 0; k < n; ++k) {
    const auto next = k + 1 < n ? quat_log(conjugate(quats_[k]) * quats_[k + 1]) : std::array<double, 3>{};
    const auto prev = k > 0 ? quat_log(conjugate(quats_[k - 1]) * quats_[k]) : next;
    const auto next_or_prev = k + 1 < n ? next : prev;
    const TangentWeights w = tangent_weights(keys_, k);
    std::array<double, 3> to_outer{}, to_inner{};
    for (int a = 0; a < 3; ++a) {
      const double outgoing = w.out_prev * prev[a] + w.out_next * next_or_prev[a];
      const double incoming = w.in_prev * prev[a] + w.in_next * next_or_prev[a];
      to_outer[a] = (outgoing - next_or_prev[a]) / 2;
      to_inner[a] = (prev[a] - incoming) / 2;
    }
    outgoing_control_.push_back(quats_[k] * quat_exp(to_outer));
    incoming_control_.push_back(quats_[k] * quat_exp(to_inner));
  }
}

Quat RotationTrack::at(double time) const {
  if (quats_.size() == 1 || time <= keys_.front().time) return quats_.front();
  if (time >= keys_.back().time) return quats_.back();
  const auto [i, u] = locate(keys_, time);
  return slerp(slerp(quats_[i], quats_[i + 1], u),
               slerp(outgoing_control_[i], incoming_control_[i + 1], u), 2 * u * (1 - u));
}

Affine AnimatedTransform::at(double time) const {
  Affine result;
  if (!translation.empty()) {
    const auto t = evaluate_vector(translation, time);
    result = Affine::translation(t[0], t[1], t[2]);
  }
  if (rotation) result = result * Affine::rotation(rotation->at(time));
  if (!scale.empty()) {
    const auto s = evaluate_vector(scale, time);
    result = result * Affine::scaling(s[0], s[1], s[2]);
  }
  return result;
}

}  // namespace nodetrace::tracer::detail::aff
