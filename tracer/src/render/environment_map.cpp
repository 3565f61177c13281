#include "nodetrace/tracer/render/environment_map.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "nodetrace/base/error.hpp"
#include "nodetrace/base/portable_math.hpp"
#include "nodetrace/tracer/render/equirectangular.hpp"
#include "scene/scene_internal.hpp"

namespace nodetrace::tracer {

namespace math = base::portable_math;  // the same directions on every machine

namespace {

constexpr double kPi = 3.14159265358979323846;

// Rec. 709 luminance, in double: a dim pixel's weight never rounds to 0.
double luminance(const Vec3& c) { return 0.2126 * double(c.x) + 0.7152 * double(c.y) + 0.0722 * double(c.z); }

// The index of the first running sum above `target` (below the last one),
// and `target`'s place within that entry's share, in [0, 1).
std::pair<std::size_t, double> find_share(const double* cdf, std::size_t count, double target) {
  const std::size_t i = std::min<std::size_t>(static_cast<std::size_t>(std::upper_bound(cdf, cdf + count, target) - cdf),
                                              count - 1);
  const double low = i == 0 ? 0.0 : cdf[i - 1];
  const double share = cdf[i] - low;
  return {i, share > 0 ? std::min((target - low) / share, 0x1.fffffffffffffp-1) : 0.0};
}

}  // namespace

EnvironmentMap::EnvironmentMap(std::string name, const Image& picture, EnvironmentSampling sampling)
    : name_(std::move(name)), sampling_(sampling) {
  if (picture.width <= 0 || picture.height <= 0) {
    throw base::FormatError(fmt::format("{}: an environment map of {}x{} pixels: expected at least one pixel", name_,
                                        picture.width, picture.height));
  }
  width_ = static_cast<std::uint32_t>(picture.width);
  height_ = static_cast<std::uint32_t>(picture.height);
  pixels_ = picture.pixels;
  static const char* const kChannel[] = {"red", "green", "blue"};
  for (std::uint32_t row = 0; row < height_; ++row) {
    for (std::uint32_t column = 0; column < width_; ++column) {
      const Vec3& c = pixels_[std::size_t{row} * width_ + column];
      lights_ = lights_ || c.x > 0 || c.y > 0 || c.z > 0;
      for (int k = 0; k < 3; ++k) {
        if (std::isfinite(c[k]) && c[k] >= 0) continue;
        throw base::FormatError(fmt::format("{}: pixel (column {}, row {} from the top) {} is {}: expected a finite, "
                                            "non-negative radiance",
                                            name_, column, row, kChannel[k], c[k]));
      }
    }
  }
  // The checksum: the pixels as a little-endian PFM stores them.
  std::uint64_t hash = detail::kFnvOffset;
  std::string bytes(std::size_t{width_} * 12, '\0');
  for (std::uint32_t stored = 0; stored < height_; ++stored) {
    const Vec3* row = &pixels_[std::size_t{height_ - 1 - stored} * width_];
    for (std::uint32_t x = 0; x < width_; ++x) {
      for (int k = 0; k < 3; ++k) {
        std::uint32_t bits;
        const float value = row[x][k];
        std::memcpy(&bits, &value, 4);
        for (int b = 0; b < 4; ++b) bytes[std::size_t{x} * 12 + std::size_t(k) * 4 + b] = char((bits >> (8 * b)) & 0xFF);
      }
    }
    hash = detail::fnv1a64(bytes, hash);
  }
  checksum_ = detail::format_hash(hash);

  // Row edges from the top, z = sin(elevation) = cos(pi r / H); a row's band
  // of the sphere has solid angle 2 pi (z_[r] - z_[r + 1]).
  z_.resize(height_ + 1);
  for (std::uint32_t r = 0; r <= height_; ++r) z_[r] = math::cos(kPi * double(r) / double(height_));
  z_[0] = 1;
  z_[height_] = -1;
  row_cdf_.resize(height_);
  column_cdf_.resize(pixels_.size());
  double rows = 0;
  for (std::uint32_t r = 0; r < height_; ++r) {
    double sum = 0;
    for (std::uint32_t c = 0; c < width_; ++c) {
      const std::size_t i = std::size_t{r} * width_ + c;
      sum += sampling_ == EnvironmentSampling::Uniform ? 1.0 : luminance(pixels_[i]);
      column_cdf_[i] = sum;
    }
    rows += sum * (z_[r] - z_[r + 1]);
    row_cdf_[r] = rows;
  }
  total_ = rows;
}

float EnvironmentMap::pdf_of(std::uint32_t column, std::uint32_t row) const {
  if (!lights_) return 0.0f;
  const double weight =
      sampling_ == EnvironmentSampling::Uniform ? 1.0 : luminance(pixels_[std::size_t{row} * width_ + column]);
  // The pixel's probability, weight x band / total, over its solid angle, 2 pi band / W.
  return static_cast<float>(weight * double(width_) / (2 * kPi * total_));
}

EnvironmentMap::LookUp EnvironmentMap::look_up(const Vec3& direction) const {
  const MapPixel p = equirectangular_pixel(direction, width_, height_);
  return {pixels_[std::size_t{p.row} * width_ + p.column], pdf_of(p.column, p.row)};
}

EnvironmentMap::Sample EnvironmentMap::sample(float u, float v) const {
  const auto [row, along_row] = find_share(row_cdf_.data(), height_, double(u) * total_);
  const double z = z_[row] + along_row * (z_[row + 1] - z_[row]);  // uniform in z: uniform in solid angle
  const double* columns = &column_cdf_[std::size_t{row} * width_];
  const auto [column, across] = find_share(columns, width_, double(v) * columns[width_ - 1]);
  const double phi = kPi * (1 - 2 * (double(column) + across) / double(width_));  // equirectangular.hpp's u
  const double horizontal = std::sqrt(std::max(0.0, 1 - z * z));
  Sample s;
  s.direction = {static_cast<float>(horizontal * math::cos(phi)), static_cast<float>(horizontal * math::sin(phi)),
                 static_cast<float>(z)};
  s.radiance = pixels_[std::size_t{row} * width_ + column];
  s.pdf = pdf_of(static_cast<std::uint32_t>(column), static_cast<std::uint32_t>(row));
  return s;
}

std::shared_ptr<const EnvironmentMap> load_environment_map(const std::string& path, EnvironmentSampling sampling) {
  return std::make_shared<const EnvironmentMap>(path, read_pfm(path, kMaxEnvironmentPixels), sampling);
}

}  // namespace nodetrace::tracer
