// Environment maps light the path tracer (issue 49 item 2): a constant map
// around a diffuse sphere is a white furnace, a diffuse plane under a sky
// with a bright patch matches its analytic irradiance with next-event
// estimation alone and combined with the bounce ray by MIS, importance
// sampling beats uniform sampling on a peaky map, camera rays that escape
// see the map's pixel, and the rays and pixels are the same whatever the
// threads, pixel order, rays in flight or sampler.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <span>
#include <vector>

#include "nodetrace/tracer/accel/kdtree.hpp"
#include "nodetrace/tracer/accel/layout.hpp"
#include "nodetrace/tracer/render/environment_map.hpp"
#include "nodetrace/tracer/render/equirectangular.hpp"
#include "nodetrace/tracer/render/render.hpp"
#include "path_render_support.hpp"
#include "test_render_scenes.hpp"

namespace nodetrace::tracer {
namespace {

using path_testing::expect_means_within_noise;
using path_testing::render;
using path_testing::Rendered;

constexpr double kPi = 3.14159265358979323846;

RenderOptions path_options(int side, std::uint32_t spp, int max_bounces, std::shared_ptr<const EnvironmentMap> map) {
  RenderOptions options;
  options.integrator = Integrator::Path;
  options.width = options.height = side;
  options.path.samples_per_pixel = spp;
  options.path.max_bounces = max_bounces;
  options.environment = std::move(map);
  return options;
}

// A map of `width` x `height` pixels of `colour(x, y from the top)`.
template <typename Colour>
std::shared_ptr<const EnvironmentMap> make_map(int width, int height, Colour colour,
                                               EnvironmentSampling sampling = EnvironmentSampling::Importance) {
  Image picture;
  picture.width = width;
  picture.height = height;
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) picture.pixels.push_back(colour(x, y));
  }
  return std::make_shared<const EnvironmentMap>("test.pfm", picture, sampling);
}

TEST(EnvironmentLight, WhiteFurnaceAConstantMapAroundADiffuseSphereGivesAlbedoTimesTheMap) {
  Scene scene = test_scenes::closed_sphere(24, 48, 1.0f, {0, 0, 0});
  scene.ambient = {0, 0, 0};
  scene.background = {9, 9, 9};  // the map replaces it: never seen
  scene.materials[0].diffuse = {0.5f, 0.25f, 0.75f};
  scene.camera = Camera{{0, 0, 4}, {0, 0, 0}, {0, 1, 0}, 8.0f};  // the sphere fills the view
  const Vec3 radiance{0.8f, 0.6f, 0.4f};
  const auto map = make_map(8, 4, [&](int, int) { return radiance; });
  const std::uint32_t spp = 32;
  const Rendered r = render(scene, path_options(10, spp, 8, map));
  // A convex object: every bounce and every shadow ray in front of the
  // surface escapes, so each sample estimates Kd x L, by light and by bounce.
  expect_means_within_noise(r.image, spp, [&](int, int) { return scene.materials[0].diffuse * radiance; });
  EXPECT_GT(r.stats.rays[static_cast<int>(RayKind::Shadow)], 0u);

  // Albedo 1: the sphere vanishes into the furnace, every pixel is L.
  scene.materials[0].diffuse = {1, 1, 1};
  scene.camera = Camera{{0, 0, 4}, {0, 0, 0}, {0, 1, 0}, 40.0f};  // the sphere and the map around it
  const Rendered white = render(scene, path_options(10, spp, 32, map));
  expect_means_within_noise(white.image, spp, [&](int, int) { return radiance; });
}

// A horizontal plane of Kd at z = 0 under a map whose upper half is a sky of
// Ls, with one pixel (column 5, row 1 from the top of 16 x 8) of Lp, and black below.
struct SkyPlane {
  static constexpr int kWidth = 16, kHeight = 8, kPatchX = 5, kPatchY = 1;
  Scene scene;
  Vec3 kd{0.7f, 0.5f, 0.3f}, sky{0.2f, 0.3f, 0.5f}, patch{40, 30, 20};
  std::shared_ptr<const EnvironmentMap> map;
  SkyPlane() {
    scene.ambient = {0, 0, 0};
    Material plane;
    plane.diffuse = kd;
    scene.materials = {plane};
    test_scenes::add_quad(scene, {-100, -100, 0}, {100, -100, 0}, {100, 100, 0}, {-100, 100, 0}, 0);
    scene.camera = Camera{{0.3f, -2, 3}, {0, 0, 0}, {0, 0, 1}, 30.0f};
    map = make_map(kWidth, kHeight, [&](int x, int y) {
      if (x == kPatchX && y == kPatchY) return patch;
      return y < kHeight / 2 ? sky : Vec3{};
    });
  }
  // Kd / pi times the irradiance: the integral of L cos(theta) over the
  // upper hemisphere, pi Ls, and the patch's excess over its pixel, whose
  // integral of z d(omega) is (2 pi / W) (z0^2 - z1^2) / 2 between its rows'
  // edges z = cos(pi r / H).
  Vec3 expected() const {
    const double z0 = std::cos(kPi * kPatchY / kHeight), z1 = std::cos(kPi * (kPatchY + 1) / kHeight);
    const double patch_cos = kPi / kWidth * (z0 * z0 - z1 * z1);
    Vec3 out;
    for (int c = 0; c < 3; ++c) {
      out[c] = static_cast<float>(kd[c] / kPi * (kPi * sky[c] + (patch[c] - sky[c]) * patch_cos));
    }
    return out;
  }
};

constexpr int kSide = 6;
constexpr std::uint32_t kSpp = 256;

TEST(EnvironmentLight, DiffusePlaneUnderASkyWithAPatchMatchesTheAnalyticIrradianceWithLightSamplingAlone) {
  const SkyPlane lit;
  const Rendered r = render(lit.scene, path_options(kSide, kSpp, 0, lit.map));
  expect_means_within_noise(r.image, kSpp, [&](int, int) { return lit.expected(); });
  // One shadow ray a sample, to the map (the black lower half is never drawn).
  EXPECT_EQ(r.stats.rays[static_cast<int>(RayKind::Shadow)], std::uint64_t(kSide * kSide) * kSpp);
}

TEST(EnvironmentLight, DiffusePlaneUnderASkyWithAPatchMatchesTheAnalyticIrradianceWithMis) {
  const SkyPlane lit;
  const Rendered r = render(lit.scene, path_options(kSide, kSpp, 1, lit.map));
  expect_means_within_noise(r.image, kSpp, [&](int, int) { return lit.expected(); });
  EXPECT_EQ(r.stats.rays[static_cast<int>(RayKind::Diffuse)], std::uint64_t(kSide * kSide) * kSpp);
}

TEST(EnvironmentLight, ABlackRoofShadowsTheSkyByItsFormFactor) {
  // Under a sky of Ls over the upper hemisphere, a plane of Kd below a black
  // rectangle at height 1 reflects Kd Ls (1 - F), F the rectangle's form
  // factor: only traced shadow and bounce rays find the roof.
  Scene scene;
  scene.ambient = {0, 0, 0};
  Material plane, roof;
  plane.diffuse = {0.7f, 0.5f, 0.3f};
  roof.diffuse = {0, 0, 0};
  scene.materials = {plane, roof};
  test_scenes::add_quad(scene, {-100, -100, 0}, {100, -100, 0}, {100, 100, 0}, {-100, 100, 0}, 0);
  const float x0 = -0.5f, x1 = 0.5f, y0 = -0.3f, y1 = 0.3f, h = 1.0f;
  test_scenes::add_quad(scene, {x0, y0, h}, {x1, y0, h}, {x1, y1, h}, {x0, y1, h}, 1);
  scene.camera = Camera{{2.0f, 0.4f, 0.6f}, {0.1f, -0.1f, 0}, {0, 0, 1}, 12.0f};  // under the roof's edge
  const Vec3 sky{0.6f, 0.8f, 1.0f};
  const auto map = make_map(8, 4, [&](int, int y) { return y < 2 ? sky : Vec3{}; });
  const int side = 6;
  const std::uint32_t spp = 2048;
  for (const int bounces : {0, 1}) {
    SCOPED_TRACE(bounces);
    const Rendered r = render(scene, path_options(side, spp, bounces, map));
    const PinholeCamera camera(*scene.camera, side, side);
    expect_means_within_noise(r.image, spp, [&](int x, int y) {
      double sum = 0;  // 1 - F, averaged over the pixel by an 8 x 8 midpoint rule
      for (int i = 0; i < 8; ++i) {
        for (int j = 0; j < 8; ++j) {
          const Ray ray = camera.ray_through(float(x) + (float(i) + 0.5f) / 8, float(y) + (float(j) + 0.5f) / 8);
          const Vec3 p = ray.origin + ray.direction * (-ray.origin.z / ray.direction.z);
          sum += 1 - path_testing::form_factor(p.x, p.y, x0, x1, y0, y1, h);
        }
      }
      return plane.diffuse * sky * float(sum / 64);
    });
  }
}

// The image's mean over its pixels and the variance of that mean.
struct ImageMean {
  double mean = 0, variance_of_mean = 0, mean_pixel_variance = 0;
};
ImageMean image_mean(const Image& image, std::uint32_t spp) {
  ImageMean m;
  const double n = double(image.pixels.size());
  for (std::size_t i = 0; i < image.pixels.size(); ++i) {
    m.mean += image.pixels[i].x / n;
    m.mean_pixel_variance += image.variance[i].x / n;
    m.variance_of_mean += image.variance[i].x / spp / (n * n);
  }
  return m;
}

TEST(EnvironmentLight, ImportanceSamplingAPeakyMapHasFarLessVarianceThanUniformSamplingAndTheSameMean) {
  SkyPlane lit;
  const auto peaky = [](int x, int y) { return x == 10 && y == 3 ? Vec3{100, 100, 100} : Vec3{}; };
  const std::uint32_t spp = 256;
  const Rendered importance =
      render(lit.scene, path_options(8, spp, 0, make_map(32, 16, peaky, EnvironmentSampling::Importance)));
  const Rendered uniform =
      render(lit.scene, path_options(8, spp, 0, make_map(32, 16, peaky, EnvironmentSampling::Uniform)));
  const ImageMean i = image_mean(importance.image, spp), u = image_mean(uniform.image, spp);
  ASSERT_GT(u.mean_pixel_variance, 0.0);
  // The patch is 1 / 500 of the sphere: uniform directions rarely find it.
  EXPECT_LT(i.mean_pixel_variance / u.mean_pixel_variance, 0.01)
      << "importance " << i.mean_pixel_variance << ", uniform " << u.mean_pixel_variance;
  // Both unbiased: the analytic value, within 3 standard errors of each mean.
  const double z0 = std::cos(kPi * 3 / 16), z1 = std::cos(kPi * 4 / 16);
  const double want = lit.kd.x / kPi * 100 * kPi / 32 * (z0 * z0 - z1 * z1);
  EXPECT_NEAR(i.mean, want, 3 * std::sqrt(i.variance_of_mean));
  EXPECT_NEAR(u.mean, want, 3 * std::sqrt(u.variance_of_mean));
}

TEST(EnvironmentLight, CameraRaysThatEscapeSeeTheMapsPixel) {
  Scene scene;  // nothing to hit
  scene.background = {9, 9, 9};
  const auto map = make_map(8, 4, [](int x, int y) { return Vec3{float(x), float(y), 1}; });
  // A narrow view about the centre of pixel (column 2, row 1 from the top).
  const Vec3 centre = equirectangular_direction(2.5 / 8, (4 - 1 - 1 + 0.5) / 4);
  scene.camera = Camera{{0, 0, 0}, centre, {0, 0, 1}, 1.0f};
  const Rendered r = render(scene, path_options(4, 3, 2, map));
  for (const Vec3& p : r.image.pixels) EXPECT_EQ(p, (Vec3{2, 1, 1}));
  for (const Vec3& v : r.image.variance) EXPECT_EQ(v, Vec3{});
}

TEST(EnvironmentLight, SameRaysWhateverTheThreadsPixelOrderRaysInFlightAndSampler) {
  const Scene scene = test_scenes::cornell_box_with_lamp();
  const auto map = make_map(16, 8, [](int x, int y) { return Vec3{0.1f * float(x), 0.2f * float(y), 0.5f}; });
  for (const PathSampler sampler : {PathSampler::Independent, PathSampler::Sobol}) {
    RenderOptions options = path_options(20, 2, 5, map);
    options.height = 15;
    options.path.sampler = sampler;
    const Rendered lit = path_testing::expect_same_rays_whatever_the_schedule(scene, options);
    // The map lights the box through its open front: more shadow rays than without it.
    options.environment = nullptr;
    const Rendered unlit = render(scene, options);
    EXPECT_GT(lit.stats.rays[static_cast<int>(RayKind::Shadow)], unlit.stats.rays[static_cast<int>(RayKind::Shadow)]);
    EXPECT_FALSE(unlit.image.pixels == lit.image.pixels);
  }
}

}  // namespace
}  // namespace nodetrace::tracer
