// An environment map: linear RGB radiance from every direction, an
// equirectangular picture (equirectangular.hpp: Blender's orientation) whose
// pixels are constant over their solid angle, with the distribution the path
// tracer's next-event estimation draws directions from. Importance sampling
// picks a pixel with probability proportional to its luminance times its
// solid angle (a marginal distribution over the rows, each row weighted by
// its band of the sphere, sin(theta) integrated over the row, then a
// conditional one over the row's columns), then a direction uniformly within
// the pixel's solid angle; so the density of a direction is its pixel's
// luminance over the map's luminance-weighted solid angle. Uniform sampling
// (tests: what importance sampling saves) picks directions uniformly over
// the sphere.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "nodetrace/tracer/geometry/vec3.hpp"
#include "nodetrace/tracer/render/image.hpp"

namespace nodetrace::tracer {

enum class EnvironmentSampling : std::uint8_t { Importance, Uniform };

// The largest map read: 2^26 pixels (8192 x 8192): 20 bytes a pixel with its distribution.
inline constexpr std::uint64_t kMaxEnvironmentPixels = std::uint64_t{1} << 26;

class EnvironmentMap {
 public:
  // `picture`'s pixels, top row first (Image's order). `name` is how the
  // errors and the trace header name the map (the file as the user typed
  // it). Throws base::FormatError, naming the map and the pixel, for a map
  // without pixels or with a value that is NaN, infinite or negative.
  EnvironmentMap(std::string name, const Image& picture, EnvironmentSampling sampling = EnvironmentSampling::Importance);

  const std::string& name() const { return name_; }
  std::uint32_t width() const { return width_; }
  std::uint32_t height() const { return height_; }
  // "fnv1a64:" and 16 hex digits: FNV-1a over the pixels' floats as stored
  // in a little-endian PFM (bottom row first, R G B), whatever the file's
  // byte order.
  const std::string& checksum() const { return checksum_; }
  EnvironmentSampling sampling() const { return sampling_; }
  // Whether any pixel is brighter than black: a black map lights nothing
  // and next-event estimation leaves it out.
  bool lights() const { return lights_; }

  // The radiance arriving from `direction` (any nonzero length), and the
  // density per solid angle with which sample() draws it.
  struct LookUp {
    Vec3 radiance;
    float pdf = 0;
  };
  LookUp look_up(const Vec3& direction) const;

  struct Sample {
    Vec3 direction;  // unit, towards the map
    Vec3 radiance;
    float pdf = 0;  // per solid angle
  };
  // A direction from two uniform numbers in [0, 1): `u` chooses the row and,
  // rescaled within the row's share, the height within it; `v` the column
  // and the angle within it (a stratified pair stays stratified). Only for
  // a map that lights().
  Sample sample(float u, float v) const;

 private:
  float pdf_of(std::uint32_t column, std::uint32_t row) const;

  std::string name_;
  std::uint32_t width_ = 0, height_ = 0;
  std::string checksum_;
  EnvironmentSampling sampling_;
  std::vector<Vec3> pixels_;  // top row first
  std::vector<double> z_;     // height + 1 row edges' z = sin(elevation), from the top: z_[0] = 1
  std::vector<double> row_cdf_;     // running sum of the rows' weights, top row first
  std::vector<double> column_cdf_;  // per row, running sum of its pixels' weights (luminance, or 1 uniform)
  bool lights_ = false;
  double total_ = 0;                // the rows' weights summed: each its pixels' weights x (z top - z bottom)
};

// The map in the colour PFM file `path` (read_pfm), named as given.
// Throws base::IoError or base::FormatError naming the file.
std::shared_ptr<const EnvironmentMap> load_environment_map(const std::string& path,
                                                           EnvironmentSampling sampling = EnvironmentSampling::Importance);

}  // namespace nodetrace::tracer
