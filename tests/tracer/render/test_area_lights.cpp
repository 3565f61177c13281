// Emissive triangles as area lights (issue 49 item 1): a Lambertian plane
// under an emissive rectangle converges to the analytic radiance, with
// next-event estimation alone and combined with the bounce rays by MIS; the
// Whitted tracer shows an emitter where its rays see it; the rays and
// pixels are the same whatever the threads, pixel order or rays in flight.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <span>
#include <vector>

#include "nodetrace/tracer/accel/kdtree.hpp"
#include "nodetrace/tracer/accel/layout.hpp"
#include "nodetrace/tracer/render/render.hpp"
#include "path_render_support.hpp"
#include "test_render_scenes.hpp"

namespace nodetrace::tracer {
namespace {

using formats::Record;
using path_testing::form_factor;
using path_testing::path_options;
using path_testing::render;
using path_testing::Rendered;

// A plane of Kd at z = 0 and, at z = 1, a black rectangle emitting Le
// downward and upward, seen from the side so the camera never sees it.
struct LitPlane {
  Scene scene;
  Vec3 kd{0.7f, 0.5f, 0.3f}, le{4.0f, 3.0f, 2.0f};
  float x0 = -0.5f, x1 = 0.5f, y0 = -0.3f, y1 = 0.3f, h = 1.0f;
  LitPlane() {
    scene.ambient = {0, 0, 0};
    Material plane, lamp;
    plane.diffuse = kd;
    lamp.diffuse = {0, 0, 0};
    lamp.emission = le;
    scene.materials = {plane, lamp};
    test_scenes::add_quad(scene, {-10, -10, 0}, {10, -10, 0}, {10, 10, 0}, {-10, 10, 0}, 0);
    test_scenes::add_quad(scene, {x0, y0, h}, {x1, y0, h}, {x1, y1, h}, {x0, y1, h}, 1);
    scene.camera = Camera{{2.0f, 0.4f, 0.6f}, {0.1f, -0.1f, 0}, {0, 0, 1}, 12.0f};
  }
  // Kd / pi times the irradiance, averaged over the pixel by an 8 x 8
  // midpoint rule.
  Vec3 expected(int x, int y, int side) const {
    const PinholeCamera camera(*scene.camera, side, side);
    double sum = 0;
    for (int i = 0; i < 8; ++i) {
      for (int j = 0; j < 8; ++j) {
        const Ray ray = camera.ray_through(float(x) + (float(i) + 0.5f) / 8, float(y) + (float(j) + 0.5f) / 8);
        const Vec3 p = ray.origin + ray.direction * (-ray.origin.z / ray.direction.z);
        sum += form_factor(p.x, p.y, x0, x1, y0, y1, h);
      }
    }
    return kd * le * float(sum / 64);
  }
};

void expect_analytic(const LitPlane& lit, const Rendered& r, int side, std::uint32_t spp) {
  int within = 0;
  for (int y = 0; y < side; ++y) {
    for (int x = 0; x < side; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * side + x;
      const Vec3 want = lit.expected(x, y, side);
      for (int c = 0; c < 3; ++c) {
        const double se = std::sqrt(double(r.image.variance[i][c]) / spp);
        ASSERT_GT(se, 0.0);
        EXPECT_NEAR(r.image.pixels[i][c], want[c], 3 * se) << "pixel " << x << "," << y << " channel " << c;
        within += std::fabs(r.image.pixels[i][c] - want[c]) <= 3 * se;
      }
    }
  }
  EXPECT_EQ(within, side * side * 3);
}

constexpr int kSide = 6;
constexpr std::uint32_t kSpp = 256;

// The lit plane rendered with `max_bounces`, checked against the analytic value.
Rendered render_lit_plane(int max_bounces) {
  const LitPlane lit;
  Rendered r = render(lit.scene, path_options(kSide, kSpp, max_bounces));
  expect_analytic(lit, r, kSide, kSpp);
  return r;
}

TEST(AreaLights, LambertPlaneUnderAnEmissiveRectangleMatchesTheAnalyticIrradianceWithLightSamplingAlone) {
  const Rendered r = render_lit_plane(0);
  // One shadow ray a sample, to the emitter.
  EXPECT_EQ(r.stats.rays[static_cast<int>(RayKind::Shadow)], std::uint64_t(kSide * kSide) * kSpp);
}

TEST(AreaLights, LambertPlaneUnderAnEmissiveRectangleMatchesTheAnalyticIrradianceWithMis) {
  const Rendered r = render_lit_plane(1);
  EXPECT_EQ(r.stats.rays[static_cast<int>(RayKind::Diffuse)], std::uint64_t(kSide * kSide) * kSpp);
}

TEST(AreaLights, CameraRaysSeeTheEmittedRadianceInBothIntegrators) {
  LitPlane lit;
  lit.scene.camera = Camera{{0, 0, 3}, {0, 0, 1}, {0, 1, 0}, 5.0f};  // the lamp's back fills the view
  RenderOptions whitted;
  whitted.width = whitted.height = 4;
  const Rendered w = render(lit.scene, whitted);
  const Rendered p = render(lit.scene, path_options(4, 4, 3));
  for (std::size_t i = 0; i < 16; ++i) {
    for (int c = 0; c < 3; ++c) {
      EXPECT_EQ(w.image.pixels[i][c], lit.le[c]);  // Whitted: the emission, no shadow rays to it
      EXPECT_EQ(p.image.pixels[i][c], lit.le[c]);  // the black lamp reflects nothing
    }
  }
  EXPECT_EQ(w.stats.rays[static_cast<int>(RayKind::Shadow)], 0u);
}

TEST(AreaLights, SameRaysWhateverTheThreadsPixelOrderAndRaysInFlight) {
  RenderOptions options = path_options(20, 2, 5);
  options.height = 15;
  const Rendered one =
      path_testing::expect_same_rays_whatever_the_schedule(test_scenes::cornell_box_with_lamp(), options);
  EXPECT_GT(one.stats.rays[static_cast<int>(RayKind::Shadow)], 0u);
}

}  // namespace
}  // namespace nodetrace::tracer
