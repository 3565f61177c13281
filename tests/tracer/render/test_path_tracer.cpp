// The path tracer (--integrator path): it converges to the right radiance
// (white furnace, a Lambertian plane under a point light, a mirror showing
// the background), casts only the rays its settings allow, survives hostile
// materials, and makes the same rays whatever the threads, pixel order, rays
// in flight or sampled rows.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
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
using path_testing::expect_means;
using path_testing::render;
using path_testing::Rendered;

RenderOptions path_options(int width, int height, std::uint32_t spp, int max_bounces) {
  RenderOptions options;
  options.integrator = Integrator::Path;
  options.width = width;
  options.height = height;
  options.path.samples_per_pixel = spp;
  options.path.max_bounces = max_bounces;
  return options;
}

TEST(PathTracer, WhiteFurnaceAConvexDiffuseObjectReflectsAlbedoTimesTheBackground) {
  Scene scene = test_scenes::closed_sphere(24, 48, 1.0f, {0, 0, 0});
  scene.ambient = {0, 0, 0};  // the background is the only light
  scene.materials[0].diffuse = {0.5f, 0.25f, 0.75f};
  scene.background = {0.8f, 0.6f, 0.4f};
  scene.camera = Camera{{0, 0, 4}, {0, 0, 0}, {0, 1, 0}, 8.0f};  // the sphere fills the view
  const std::uint32_t spp = 16;
  const Rendered r = render(scene, path_options(12, 12, spp, 8));
  expect_means(r.image, spp, [&](int, int) { return scene.materials[0].diffuse * scene.background; }, 1e-6f);
  // Every camera ray hits, every diffuse bounce escapes: one bounce a sample.
  EXPECT_EQ(r.stats.rays[static_cast<int>(RayKind::Primary)], 12u * 12u * spp);
  EXPECT_EQ(r.stats.rays[static_cast<int>(RayKind::Diffuse)], 12u * 12u * spp);
}

TEST(PathTracer, WhiteFurnaceADiffuseAndMirrorObjectReflectsTheSumOfItsLobes) {
  // The mixture rule: each bounce picks the diffuse or the mirror lobe by
  // weight, and the pixel converges to (Kd + reflectance) x background.
  Scene scene = test_scenes::closed_sphere(24, 48, 1.0f, {0, 0, 0});
  scene.ambient = {0, 0, 0};
  scene.materials[0].diffuse = {0.3f, 0.2f, 0.1f};
  scene.materials[0].reflectance = 0.4f;
  scene.background = {0.8f, 0.6f, 0.4f};
  scene.camera = Camera{{0, 0, 4}, {0, 0, 0}, {0, 1, 0}, 8.0f};
  const std::uint32_t spp = 256;
  const Rendered r = render(scene, path_options(6, 6, spp, 8));
  const Vec3 albedo = scene.materials[0].diffuse + Vec3{0.4f, 0.4f, 0.4f};
  expect_means(r.image, spp, [&](int, int) { return albedo * scene.background; }, 1e-6f);
  EXPECT_GT(r.stats.rays[static_cast<int>(RayKind::Reflection)], 0u);
  EXPECT_GT(r.stats.rays[static_cast<int>(RayKind::Diffuse)], 0u);
}

TEST(PathTracer, LambertPlaneUnderOnePointLightMatchesTheAnalyticValue) {
  Scene scene;
  scene.ambient = {0, 0, 0};  // the light is the only light
  Material matte;
  matte.diffuse = {0.7f, 0.5f, 0.3f};
  scene.materials = {matte};
  test_scenes::add_quad(scene, {-10, -10, 0}, {10, -10, 0}, {10, 10, 0}, {-10, 10, 0}, 0);
  const PointLight light{{0.3f, -0.2f, 2.0f}, {0.9f, 1.0f, 0.8f}};
  scene.lights = {light};
  scene.camera = Camera{{0, 0, 3}, {0, 0, 0}, {0, 1, 0}, 20.0f};
  const int side = 8;
  const std::uint32_t spp = 64;
  const Rendered r = render(scene, path_options(side, side, spp, 1));
  // The analytic radiance Kd cos(theta) times the light at each point,
  // averaged over the pixel by a 32 x 32 midpoint rule (far finer than the
  // samples' standard error).
  const PinholeCamera camera(*scene.camera, side, side);
  expect_means(r.image, spp, [&](int x, int y) {
    double sum = 0;
    for (int i = 0; i < 32; ++i) {
      for (int j = 0; j < 32; ++j) {
        const Ray ray = camera.ray_through(float(x) + (float(i) + 0.5f) / 32, float(y) + (float(j) + 0.5f) / 32);
        const Vec3 point = ray.origin + ray.direction * (-ray.origin.z / ray.direction.z);
        const Vec3 to_light = light.position - point;
        sum += to_light.z / length(to_light);
      }
    }
    return matte.diffuse * light.color * float(sum / (32 * 32));
  }, 1e-5f);
  EXPECT_EQ(r.stats.rays[static_cast<int>(RayKind::Shadow)], std::uint64_t(side * side) * spp);
}

TEST(PathTracer, APerfectMirrorShowsTheBackgroundExactly) {
  Scene scene;  // a mirror's ambient colour is Kd: black here
  Material mirror;
  mirror.diffuse = {0, 0, 0};
  mirror.reflectance = 1;
  scene.materials = {mirror};
  test_scenes::add_quad(scene, {-10, -10, 0}, {10, -10, 0}, {10, 10, 0}, {-10, 10, 0}, 0);
  scene.background = {0.2f, 0.4f, 0.6f};
  scene.camera = Camera{{0, -2, 1}, {0, 0, 0}, {0, 0, 1}, 40.0f};
  const Rendered r = render(scene, path_options(16, 12, 4, 3));
  for (std::size_t i = 0; i < r.image.pixels.size(); ++i) {
    EXPECT_EQ(r.image.pixels[i], scene.background) << "pixel " << i;
    EXPECT_EQ(r.image.variance[i], Vec3{}) << "pixel " << i;
  }
  EXPECT_GT(r.stats.rays[static_cast<int>(RayKind::Reflection)], 0u);
  EXPECT_EQ(r.stats.rays[static_cast<int>(RayKind::Shadow)], 0u);
}

TEST(PathTracer, AHalfSilveredMirrorShowsHalfTheBackground) {
  Scene scene;
  Material mirror;
  mirror.diffuse = {0, 0, 0};
  mirror.reflectance = 0.5f;
  scene.materials = {mirror};
  test_scenes::add_quad(scene, {-10, -10, 0}, {10, -10, 0}, {10, 10, 0}, {-10, 10, 0}, 0);
  scene.background = {0.2f, 0.4f, 0.6f};
  scene.camera = Camera{{0, -0.5f, 3}, {0, 0, 0}, {0, 0, 1}, 20.0f};  // the plane fills the view
  const Rendered r = render(scene, path_options(8, 6, 2, 3));
  for (const Vec3& p : r.image.pixels) EXPECT_EQ(p, scene.background * 0.5f);
}

TEST(PathTracer, NoBouncesTracesExactlyTheCameraRaysAndTheirShadowRays) {
  const Scene scene = test_scenes::cornell_box();
  const std::uint32_t spp = 3;
  const Rendered r = render(scene, path_options(20, 15, spp, 0));
  EXPECT_EQ(r.stats.rays[static_cast<int>(RayKind::Primary)], 20u * 15u * spp);
  EXPECT_GT(r.stats.rays[static_cast<int>(RayKind::Shadow)], 0u);
  EXPECT_EQ(r.stats.total_rays(), r.stats.rays[0] + r.stats.rays[1]);
  // With bounces the same camera and shadow rays come first in each sample:
  // the records grow, the camera rays stay.
  const Rendered more = render(scene, path_options(20, 15, spp, 4));
  EXPECT_EQ(more.stats.rays[static_cast<int>(RayKind::Primary)], r.stats.rays[0]);
  EXPECT_GT(more.records.size(), r.records.size());
  const KdTree tree = KdTree::build(scene.triangles);
  EXPECT_EQ(Renderer(scene, tree, make_layout(tree, LayoutKind::Dfl), path_options(20, 15, spp, 0))
                .ray_plan()
                .cast,
            (std::array<bool, kRayKindCount>{true, true, false, false, false, false}));
}

TEST(PathTracer, HostileMaterialsAreCountedNeverCrash) {
  Scene scene = test_scenes::cornell_box();
  scene.materials[4].ior = 0;               // the glass block: refraction from nothing
  scene.materials[3].shininess = 1e30f;     // the mirror block: a glossy lobe of absurd exponent
  scene.materials[3].specular = {1, 1, 1};
  scene.materials[0].diffuse = {3e38f, 3e38f, 3e38f};  // walls whose throughput overflows
  const Rendered r = render(scene, path_options(24, 18, 2, 6));
  EXPECT_GT(r.stats.nonfinite_samples, 0u);
  EXPECT_LT(r.stats.nonfinite_samples, 24u * 18u * 2u);
  for (const Vec3& p : r.image.pixels) {
    EXPECT_TRUE(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z));
  }
  for (const Vec3& v : r.image.variance) EXPECT_FALSE(std::isnan(v.x) || std::isnan(v.y) || std::isnan(v.z));
}

TEST(PathTracer, NoLightAndABlackBackgroundIsBlack) {
  Scene scene = test_scenes::cornell_box(true, true, /*light=*/false);
  scene.ambient = {0, 0, 0};
  const Rendered r = render(scene, path_options(16, 12, 2, 4));
  for (const Vec3& p : r.image.pixels) EXPECT_EQ(p, Vec3{});
  EXPECT_GT(r.records.size(), 16u * 12u * 2u);
}

// Sorted, the unit dropped: the same fetches in any order.
std::vector<std::pair<std::uint64_t, int>> as_multiset(const std::vector<Record>& records) {
  std::vector<std::pair<std::uint64_t, int>> all;
  for (const Record& r : records) all.emplace_back(r.address, int(r.tag));
  std::sort(all.begin(), all.end());
  return all;
}

TEST(PathTracer, SameRaysWhateverTheThreadsPixelOrderRaysInFlightAndSampledRows) {
  Scene scene = test_scenes::cornell_box();
  scene.materials[0].specular = {0.3f, 0.3f, 0.3f};  // white walls get a glossy lobe too
  scene.materials[0].shininess = 20;
  scene.background = {0.1f, 0.1f, 0.2f};
  RenderOptions options = path_options(24, 18, 2, 5);
  options.pixels_per_chunk = 13;
  options.threads = 1;
  const Rendered one = render(scene, options);
  ASSERT_GT(one.stats.rays[static_cast<int>(RayKind::Diffuse)], 0u);
  ASSERT_GT(one.stats.rays[static_cast<int>(RayKind::Glossy)], 0u);
  ASSERT_GT(one.stats.rays[static_cast<int>(RayKind::Refraction)], 0u);

  options.threads = 2;
  const Rendered two = render(scene, options);
  EXPECT_TRUE(two.records == one.records);
  EXPECT_TRUE(two.image.pixels == one.image.pixels);
  EXPECT_TRUE(two.image.variance == one.image.variance);

  options.pixel_order = PixelOrder::Tiled;
  const Rendered tiled = render(scene, options);
  EXPECT_FALSE(tiled.records == one.records);
  EXPECT_TRUE(as_multiset(tiled.records) == as_multiset(one.records));
  EXPECT_TRUE(tiled.image.pixels == one.image.pixels);
  options.pixel_order = PixelOrder::Scanline;

  options.rays_in_flight = 1;
  options.units = 1;
  std::vector<Record> in_flight_one;
  {
    const KdTree tree = KdTree::build(scene.triangles);
    const Renderer renderer(scene, tree, make_layout(tree, LayoutKind::Dfl), options);
    renderer.render_in_flight(
        [&](std::span<const Record> r) { in_flight_one.insert(in_flight_one.end(), r.begin(), r.end()); }, nullptr);
  }
  EXPECT_TRUE(in_flight_one == one.records);  // one slot of one unit: the sequential order
  options.rays_in_flight = 32;
  const Rendered thirty_two = render(scene, options);
  EXPECT_FALSE(thirty_two.records == one.records);
  EXPECT_TRUE(as_multiset(thirty_two.records) == as_multiset(one.records));
  EXPECT_TRUE(thirty_two.image.pixels == one.image.pixels);
  options.rays_in_flight = 1;

  // Rows 5 to 11 alone trace what the full render traces there: the full
  // render split at row 5 is the render of rows 0-4 then the rest.
  const std::vector<Renderer::PixelRun> head{{0, 5 * 24}}, rows{{5 * 24, 12 * 24}}, tail{{12 * 24, 18 * 24}};
  const Rendered first = render(scene, options, &head), middle = render(scene, options, &rows),
                 last = render(scene, options, &tail);
  ASSERT_EQ(first.records.size() + middle.records.size() + last.records.size(), one.records.size());
  EXPECT_TRUE(std::equal(middle.records.begin(), middle.records.end(), one.records.begin() + first.records.size()));
  for (std::size_t p = 5 * 24; p < 12 * 24; ++p) EXPECT_EQ(middle.image.pixels[p], one.image.pixels[p]);
}

TEST(PathTracer, CastRaysListsEveryRayTheRenderCastsWithItsKind) {
  const Scene scene = test_scenes::cornell_box();
  for (const Integrator integrator : {Integrator::Path, Integrator::Whitted}) {
    RenderOptions options = path_options(12, 9, 2, 5);
    options.integrator = integrator;
    const Rendered r = render(scene, options);
    const KdTree tree = KdTree::build(scene.triangles);
    const Renderer renderer(scene, tree, make_layout(tree, LayoutKind::Dfl), options);
    std::array<std::uint64_t, kRayKindCount> counts{};
    const auto rays = renderer.cast_rays(0, 12 * 9);
    for (const auto& cast : rays) ++counts[static_cast<int>(cast.kind)];
    EXPECT_EQ(counts, r.stats.rays);
    ASSERT_FALSE(rays.empty());
    EXPECT_EQ(rays.front().kind, RayKind::Primary);
    // Tracing the listed rays one by one fetches what the render fetched.
    std::vector<Record> records;
    for (const auto& cast : rays) {
      if (cast.kind == RayKind::Shadow) {
        renderer.occluded(cast.ray, 1.0f - 1e-4f, &records, nullptr);
      } else {
        renderer.closest_hit(cast.ray, std::numeric_limits<float>::infinity(), &records, nullptr);
      }
    }
    EXPECT_TRUE(records == r.records);
  }
}

TEST(PathTracer, PlanListsTheKindsTheSceneCanCast) {
  const Scene glassless = test_scenes::cornell_box(true, /*glass=*/false);
  const RayKindPlan plan = plan_path_ray_kinds(glassless, 5);
  EXPECT_TRUE(plan.casts(RayKind::Diffuse));
  EXPECT_TRUE(plan.casts(RayKind::Reflection));
  EXPECT_FALSE(plan.casts(RayKind::Refraction));
  EXPECT_EQ(plan.why_not[static_cast<int>(RayKind::Refraction)], "no material transmits");
  EXPECT_FALSE(plan.casts(RayKind::Glossy));
  EXPECT_EQ(plan.kinds.size(), 6u);
  EXPECT_EQ(plan_ray_kinds(glassless, 10).kinds.size(), 4u);  // Whitted's header keeps its four kinds
}

}  // namespace
}  // namespace nodetrace::tracer
