// The low-discrepancy sampler (--sampler sobol, issue 49 item 5): its
// pieces are what they claim (Sobol's second dimension, a (0, 2)-net per
// pixel, permutations), it lowers the error at equal samples, and its rays
// are the same whatever the threads and pixel order.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <span>
#include <vector>

#include "nodetrace/tracer/accel/kdtree.hpp"
#include "nodetrace/tracer/accel/layout.hpp"
#include "nodetrace/tracer/render/render.hpp"
#include "render/path_random.hpp"
#include "render/sobol.hpp"
#include "test_render_scenes.hpp"

namespace nodetrace::tracer {
namespace {

using formats::Record;

TEST(SobolSampler, TheSecondDimensionIsSobols) {
  const double expected[] = {0, 0.5, 0.75, 0.25, 0.625, 0.125, 0.375, 0.875};  // by index, not Gray code
  for (std::uint32_t i = 0; i < 8; ++i) EXPECT_EQ(detail::sobol_bits(i, 1) * 0x1p-32, expected[i]) << i;
  for (std::uint32_t i = 0; i < 8; ++i) EXPECT_EQ(detail::sobol_bits(i, 0), detail::reverse_bits(i)) << i;
}

TEST(SobolSampler, PermutedIsAPermutation) {
  for (const std::uint32_t n : {1u, 2u, 3u, 7u, 16u, 100u, 1000u}) {
    for (const std::uint32_t seed : {0u, 1u, 0xdeadbeefu}) {
      std::set<std::uint32_t> seen;
      for (std::uint32_t i = 0; i < n; ++i) seen.insert(detail::permuted(i, n, seed));
      EXPECT_EQ(seen.size(), n);
      EXPECT_LT(*seen.rbegin(), n);
    }
  }
}

// The 16 samples of a pixel put one point of each 2D pair in every
// elementary interval of area 1/16: 1 x 16, 2 x 8, 4 x 4, 8 x 2 and 16 x 1.
TEST(SobolSampler, EachPairOfAPixelsSixteenSamplesIsAZeroTwoNet) {
  struct Pair {
    std::uint32_t bounce, first, second;
  };
  for (const Pair pair : {Pair{0, detail::kPixelX, detail::kPixelY}, Pair{2, detail::kDirection1, detail::kDirection2},
                          Pair{1, detail::kEmitterU, detail::kEmitterV}}) {
    for (const std::uint32_t pixel : {0u, 77u}) {
      for (int a = 0; a <= 4; ++a) {
        std::set<std::pair<int, int>> cells;
        for (std::uint32_t s = 0; s < 16; ++s) {
          const detail::PathRandom random(3, pixel, s, PathSampler::Sobol, 16);
          const float u = random.uniform(pair.bounce, pair.first), v = random.uniform(pair.bounce, pair.second);
          cells.insert({int(u * float(1 << a)), int(v * float(1 << (4 - a)))});
        }
        EXPECT_EQ(cells.size(), 16u) << "pair " << pair.first << " pixel " << pixel << " a " << a;
      }
    }
  }
}

struct Rendered {
  std::vector<Record> records;
  Image image;
};

Rendered render(const Scene& scene, const RenderOptions& options) {
  const KdTree tree = KdTree::build(scene.triangles);
  const Renderer renderer(scene, tree, make_layout(tree, LayoutKind::Dfl), options);
  Rendered out;
  renderer.render([&](std::span<const Record> r) { out.records.insert(out.records.end(), r.begin(), r.end()); },
                  &out.image);
  return out;
}

// A Lambertian plane lit by an emissive rectangle, at 16 samples: the
// RMSE against a 4096-sample render is at most 0.6 of the independent
// sampler's.
TEST(SobolSampler, LowersTheErrorOfADirectlyLitPlaneToAtMostSixTenths) {
  Scene scene;
  scene.ambient = {0, 0, 0};
  Material plane, lamp;
  plane.diffuse = {0.7f, 0.7f, 0.7f};
  lamp.diffuse = {0, 0, 0};
  lamp.emission = {3, 3, 3};
  scene.materials = {plane, lamp};
  test_scenes::add_quad(scene, {-10, -10, 0}, {10, -10, 0}, {10, 10, 0}, {-10, 10, 0}, 0);
  test_scenes::add_quad(scene, {-0.5f, -0.3f, 1}, {0.5f, -0.3f, 1}, {0.5f, 0.3f, 1}, {-0.5f, 0.3f, 1}, 1);
  test_scenes::add_box(scene, {-0.2f, -0.2f, 0}, {0.2f, 0.2f, 0.4f}, 0);  // a shadow's edges
  scene.camera = Camera{{3.0f, 0.5f, 1.5f}, {0, 0, 0}, {0, 0, 1}, 40.0f};
  RenderOptions options;
  options.integrator = Integrator::Path;
  options.width = options.height = 16;
  options.path.max_bounces = 1;
  options.path.samples_per_pixel = 4096;
  const Rendered reference = render(scene, options);
  options.path.samples_per_pixel = 16;
  const auto rmse = [&](PathSampler sampler) {
    options.path.sampler = sampler;
    const Rendered r = render(scene, options);
    double sum = 0;
    for (std::size_t i = 0; i < r.image.pixels.size(); ++i) {
      const double d = double(r.image.pixels[i].x) - double(reference.image.pixels[i].x);
      sum += d * d;
    }
    return std::sqrt(sum / double(r.image.pixels.size()));
  };
  const double independent = rmse(PathSampler::Independent), sobol = rmse(PathSampler::Sobol);
  EXPECT_LE(sobol, 0.6 * independent) << "sobol " << sobol << " independent " << independent;
}

// The Cornell box under a dim blue sky.
Scene lit_cornell_box() {
  Scene scene = test_scenes::cornell_box();
  scene.background = {0.1f, 0.1f, 0.2f};
  return scene;
}

RenderOptions path_options(int width, int height, std::uint32_t spp) {
  RenderOptions options;
  options.integrator = Integrator::Path;
  options.width = width;
  options.height = height;
  options.path.samples_per_pixel = spp;
  return options;
}

// The hashes a render worker keeps for its pixel (SobolHashCache) give the
// numbers computed afresh, whatever order pixels, samples and bounces come
// in, beyond the kept bounces and pairs too.
TEST(SobolSampler, KeptHashesGiveTheNumbersComputedAfresh) {
  detail::SobolHashCache kept;
  int compared = 0;
  for (const std::uint64_t frame : {std::uint64_t{0}, std::uint64_t{3} << 32}) {
    for (const std::uint32_t pixel : {5u, 6u, 5u, 1000u}) {
      for (std::uint32_t sample = 0; sample < 8; ++sample) {
        const detail::PathRandom fresh(frame, pixel, sample, PathSampler::Sobol, 8, 9);
        const detail::PathRandom cached(frame, pixel, sample, PathSampler::Sobol, 8, 9, &kept);
        for (const std::uint32_t bounce : {0u, 1u, 2u, 63u, 64u, 70u}) {
          for (std::uint32_t dimension = 0; dimension < 20; ++dimension) {
            ASSERT_EQ(cached.uniform(bounce, dimension), fresh.uniform(bounce, dimension))
                << frame << " " << pixel << " " << sample << " " << bounce << " " << dimension;
            const auto a = cached.uniform_pair(bounce, dimension), b = fresh.uniform_pair(bounce, dimension);
            ASSERT_EQ(a.first, b.first);
            ASSERT_EQ(a.second, b.second);
            ++compared;
          }
        }
      }
    }
  }
  EXPECT_EQ(compared, 2 * 4 * 8 * 6 * 20);
}

// --path-seed: each seed is another render of the same picture, with the
// same bytes for any thread count.
TEST(SobolSampler, PathSeedsGiveOtherNumbersOfTheSameMeanWithTheSameBytesForAnyThreads) {
  const Scene scene = lit_cornell_box();
  RenderOptions options = path_options(16, 12, 16);
  for (const PathSampler sampler : {PathSampler::Independent, PathSampler::Sobol}) {
    options.path.sampler = sampler;
    options.threads = 1;
    options.path.seed = 0;
    const Rendered zero = render(scene, options);
    options.path.seed = 1;
    const Rendered one = render(scene, options);
    options.threads = 2;
    EXPECT_TRUE(render(scene, options).image.pixels == one.image.pixels);
    EXPECT_FALSE(one.image.pixels == zero.image.pixels);
    // The whole image's mean agrees within 3 standard errors (from the
    // pixels' variances: independent pixels, so they add).
    double mean_zero = 0, mean_one = 0, variance = 0;
    const double n = double(zero.image.pixels.size());
    for (std::size_t i = 0; i < zero.image.pixels.size(); ++i) {
      mean_zero += zero.image.pixels[i].x / n;
      mean_one += one.image.pixels[i].x / n;
      variance += (zero.image.variance[i].x + one.image.variance[i].x) / 16.0 / (n * n);
    }
    EXPECT_NEAR(mean_one, mean_zero, 3 * std::sqrt(variance)) << int(sampler);
  }
}

TEST(SobolSampler, SameRaysWhateverTheThreadsAndPixelOrder) {
  const Scene scene = lit_cornell_box();
  RenderOptions options = path_options(20, 15, 4);
  options.path.sampler = PathSampler::Sobol;
  options.pixels_per_chunk = 13;
  options.threads = 1;
  const Rendered one = render(scene, options);
  options.threads = 2;
  const Rendered two = render(scene, options);
  EXPECT_TRUE(two.records == one.records);
  EXPECT_TRUE(two.image.pixels == one.image.pixels);
  options.pixel_order = PixelOrder::Tiled;
  EXPECT_TRUE(render(scene, options).image.pixels == one.image.pixels);
  options.pixel_order = PixelOrder::Scanline;
  options.path.sampler = PathSampler::Independent;
  EXPECT_FALSE(render(scene, options).image.pixels == one.image.pixels);
}

}  // namespace
}  // namespace nodetrace::tracer
