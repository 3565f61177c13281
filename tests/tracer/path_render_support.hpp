// What the path tracer's suites share: a render into memory (records,
// totals, image) and the check of every pixel's mean against an expected
// radiance within 3 standard errors.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <span>
#include <vector>

#include "nodetrace/tracer/accel/kdtree.hpp"
#include "nodetrace/tracer/accel/layout.hpp"
#include "nodetrace/tracer/render/render.hpp"

namespace nodetrace::tracer::path_testing {

struct Rendered {
  std::vector<formats::Record> records;
  RenderStats stats;
  Image image;
};

// Path tracing a side x side image.
inline RenderOptions path_options(int side, std::uint32_t spp, int max_bounces) {
  RenderOptions options;
  options.integrator = Integrator::Path;
  options.width = options.height = side;
  options.path.samples_per_pixel = spp;
  options.path.max_bounces = max_bounces;
  return options;
}

// Renders every pixel over a kd-tree in DFL layout, or only `runs` of the
// pixel sequence when given.
inline Rendered render(const Scene& scene, const RenderOptions& options,
                       const std::vector<Renderer::PixelRun>* runs = nullptr) {
  const KdTree tree = KdTree::build(scene.triangles);
  const Layout layout = make_layout(tree, LayoutKind::Dfl);
  const Renderer renderer(scene, tree, layout, options);
  Rendered out;
  const auto sink = [&](std::span<const formats::Record> r) {
    out.records.insert(out.records.end(), r.begin(), r.end());
  };
  out.stats = runs ? renderer.render_runs(*runs, {}, sink, &out.image) : renderer.render(sink, &out.image);
  return out;
}

// Every pixel's mean is `expected(x, y)` within 3 of its standard errors
// (sqrt(variance / spp)), or within `floor` where the samples agree exactly.
template <typename Expected>
void expect_means(const Image& image, std::uint32_t spp, Expected expected, float floor) {
  ASSERT_EQ(image.variance.size(), image.pixels.size());
  int checked = 0;
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * image.width + x;
      const Vec3 want = expected(x, y);
      for (int c = 0; c < 3; ++c) {
        const double se = std::sqrt(double(image.variance[i][c]) / spp);
        EXPECT_NEAR(image.pixels[i][c], want[c], std::max(3 * se, double(floor)))
            << "pixel " << x << "," << y << " channel " << c;
        ++checked;
      }
    }
  }
  EXPECT_EQ(checked, image.width * image.height * 3);
}

// The same check made robust to the number of pixels: of hundreds of
// pixel means, a few lie beyond 3 standard errors by chance (0.27% each),
// so it asserts that the image's mean error in each channel is within 3
// standard errors of that mean (pixels are independent, channels are not), that at most one pixel in 50 (and at least one allowed) has a
// channel beyond 3 of its standard errors, and no channel beyond 5. A
// biased estimator fails the first; an error confined to a few pixels, the
// last.
template <typename Expected>
void expect_means_within_noise(const Image& image, std::uint32_t spp, Expected expected) {
  ASSERT_EQ(image.variance.size(), image.pixels.size());
  std::array<double, 3> error_sum{}, variance_sum{};
  int pixels_beyond3 = 0, count = 0;
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * image.width + x;
      const Vec3 want = expected(x, y);
      bool beyond3 = false;
      for (int c = 0; c < 3; ++c) {
        const double error = double(image.pixels[i][c]) - double(want[c]);
        const double variance = double(image.variance[i][c]) / spp;
        const double se = std::sqrt(variance);
        error_sum[c] += error;
        variance_sum[c] += variance;
        ++count;
        beyond3 = beyond3 || std::fabs(error) > 3 * se;
        EXPECT_LE(std::fabs(error), std::max(5 * se, 1e-6)) << "pixel " << x << "," << y << " channel " << c;
      }
      pixels_beyond3 += beyond3;
    }
  }
  for (int c = 0; c < 3; ++c) {
    EXPECT_LE(std::fabs(error_sum[c]), std::max(3 * std::sqrt(variance_sum[c]), 1e-6 * count))
        << "channel " << c << ": mean error " << error_sum[c] * 3 / count << ", its standard error "
        << std::sqrt(variance_sum[c]) * 3 / count;
  }
  const int pixels = image.width * image.height;
  EXPECT_LE(pixels_beyond3, std::max(1, pixels / 50)) << pixels_beyond3 << " of " << pixels
                                                      << " pixels beyond 3 standard errors";
}

// The form factor from a point to a rectangle parallel to its surface, at
// height h, with one corner straight above it and sides x and y (signed:
// the rectangle's other corner at (x, y)).
inline double corner_form_factor(double x, double y, double h) {
  const double X = std::fabs(x) / h, Y = std::fabs(y) / h;
  const double a = std::sqrt(1 + X * X), b = std::sqrt(1 + Y * Y);
  const double f = (X / a * std::atan(Y / a) + Y / b * std::atan(X / b)) / (2 * 3.14159265358979323846);
  return (x < 0) != (y < 0) ? -f : f;
}

// The rectangle [x0, x1] x [y0, y1] at height h over the point (px, py, 0):
// irradiance / (pi Le), by inclusion and exclusion of corner rectangles.
inline double form_factor(double px, double py, double x0, double x1, double y0, double y1, double h) {
  return corner_form_factor(x1 - px, y1 - py, h) - corner_form_factor(x0 - px, y1 - py, h) -
         corner_form_factor(x1 - px, y0 - py, h) + corner_form_factor(x0 - px, y0 - py, h);
}

// Renders `options` on one thread, then checks that two threads give the
// same records and pixels, the Morton order the same pixels, and 16 rays in
// flight as many records and the same pixels. Returns the first render.
inline Rendered expect_same_rays_whatever_the_schedule(const Scene& scene, RenderOptions options) {
  options.pixels_per_chunk = 13;
  options.threads = 1;
  const Rendered one = render(scene, options);
  options.threads = 2;
  const Rendered two = render(scene, options);
  EXPECT_TRUE(two.records == one.records);
  EXPECT_TRUE(two.image.pixels == one.image.pixels);
  EXPECT_TRUE(two.image.variance == one.image.variance);
  options.pixel_order = PixelOrder::Morton;
  const Rendered morton = render(scene, options);
  EXPECT_TRUE(morton.image.pixels == one.image.pixels);
  options.pixel_order = PixelOrder::Scanline;
  options.rays_in_flight = 16;
  const Rendered in_flight = render(scene, options);
  EXPECT_EQ(in_flight.records.size(), one.records.size());
  EXPECT_TRUE(in_flight.image.pixels == one.image.pixels);
  return one;
}

}  // namespace nodetrace::tracer::path_testing
