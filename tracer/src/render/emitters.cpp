#include "render/emitters.hpp"

#include <algorithm>
#include <cmath>

namespace nodetrace::tracer::detail {

namespace {

float mean(const Vec3& v) { return (v.x + v.y + v.z) / 3; }

}  // namespace

bool emits(const Material& material) {
  return material.emission.x > 0 || material.emission.y > 0 || material.emission.z > 0;
}

Emitters::Emitters(const Scene& scene) : scene_(scene) {
  std::vector<double> power;
  for (std::uint32_t t = 0; t < scene.triangles.size(); ++t) {
    const Triangle& triangle = scene.triangles[t];
    if (triangle.material >= scene.materials.size() || !emits(scene.materials[triangle.material])) continue;
    const double area = 0.5 * double(length(cross(triangle.v1 - triangle.v0, triangle.v2 - triangle.v0)));
    const double p = area * double(mean(scene.materials[triangle.material].emission));
    if (!(p > 0) || !std::isfinite(p)) continue;
    triangles_.push_back(t);
    cdf_.push_back((cdf_.empty() ? 0.0 : cdf_.back()) + p);
    power.push_back(p);
  }
  if (triangles_.empty()) return;
  pdf_area_.assign(scene.triangles.size(), 0.0f);
  const double total = cdf_.back();
  for (std::size_t i = 0; i < triangles_.size(); ++i) {
    const Triangle& triangle = scene.triangles[triangles_[i]];
    const double area = 0.5 * double(length(cross(triangle.v1 - triangle.v0, triangle.v2 - triangle.v0)));
    pdf_area_[triangles_[i]] = static_cast<float>(power[i] / total / area);
  }
}

Emitters::Sample Emitters::sample(float u, float v) const {
  const double target = double(u) * cdf_.back();
  const auto found = std::upper_bound(cdf_.begin(), cdf_.end(), target);
  const std::size_t i = std::min<std::size_t>(static_cast<std::size_t>(found - cdf_.begin()), triangles_.size() - 1);
  const double low = i == 0 ? 0.0 : cdf_[i - 1];
  // u's place within the chosen emitter's share, below 1.
  const float u1 = std::min(static_cast<float>((target - low) / (cdf_[i] - low)), 0x1.fffffep-1f);
  const float u2 = v;
  const std::uint32_t t = triangles_[i];
  const Triangle& triangle = scene_.triangles[t];
  // Uniform on the triangle: the square-root warp (sqrt is exactly rounded everywhere).
  const float root = std::sqrt(u1);
  const float b0 = 1 - root, b1 = u2 * root;
  Sample s;
  s.point = triangle.v0 * b0 + triangle.v1 * b1 + triangle.v2 * (1 - b0 - b1);
  s.normal = normalize(cross(triangle.v1 - triangle.v0, triangle.v2 - triangle.v0));
  s.radiance = scene_.materials[triangle.material].emission;
  s.pdf_area = pdf_area_[t];
  return s;
}

float Emitters::pdf_area(std::uint32_t triangle) const {
  return triangle < pdf_area_.size() ? pdf_area_[triangle] : 0.0f;
}

}  // namespace nodetrace::tracer::detail
