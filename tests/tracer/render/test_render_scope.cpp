// The options that narrow a render for the study of the paper's open
// choices: --rays (primary, primary+shadow) and --lights first each change
// what they say and nothing else.
#include <gtest/gtest.h>

#include <limits>

#include "nodetrace/tracer/accel/kdtree.hpp"
#include "nodetrace/tracer/accel/layout.hpp"
#include "nodetrace/tracer/render/camera.hpp"
#include "nodetrace/tracer/render/interaction.hpp"
#include "nodetrace/tracer/render/render.hpp"
#include "test_render_scenes.hpp"
#include "test_support.hpp"

namespace nodetrace::tracer {
namespace {

using formats::Record;
constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr int kWidth = 40, kHeight = 30;

RenderOptions small_options() {
  RenderOptions options;
  options.width = kWidth;
  options.height = kHeight;
  options.threads = 2;
  return options;
}

struct Rendered {
  std::vector<Record> records;
  RenderStats stats;
};

Rendered render(const Scene& scene, const RenderOptions& options) {
  const KdTree tree = KdTree::build(scene.triangles);
  const Layout layout = make_layout(tree, LayoutKind::Hybrid, 4);
  const Renderer renderer(scene, tree, layout, options);
  Rendered out;
  out.stats = renderer.render(
      [&](std::span<const Record> r) { out.records.insert(out.records.end(), r.begin(), r.end()); }, nullptr);
  return out;
}

TEST(RenderScopeTest, PrimaryOnlyRecordsAreThePrimaryRaysFetchesAlone) {
  const Scene scene = test_scenes::cornell_box();  // a light, a mirror and glass: every kind is needed
  RenderOptions options = small_options();
  options.rays = RayScope::Primary;
  const Rendered primary = render(scene, options);

  // The same tree and layout: each pixel's primary ray, in scanline order.
  const KdTree tree = KdTree::build(scene.triangles);
  const Layout layout = make_layout(tree, LayoutKind::Hybrid, 4);
  const Renderer probe(scene, tree, layout, small_options());
  const PinholeCamera camera(*scene.camera, kWidth, kHeight);
  std::vector<Record> expected;
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) probe.closest_hit(camera.primary_ray(x, y), kInf, &expected, nullptr);
  }
  ASSERT_GT(expected.size(), std::size_t{kWidth * kHeight});
  EXPECT_EQ(primary.records.size(), expected.size());
  EXPECT_TRUE(primary.records == expected);
  EXPECT_EQ(primary.stats.rays[0], std::uint64_t{kWidth * kHeight});
  EXPECT_EQ(primary.stats.rays[1] + primary.stats.rays[2] + primary.stats.rays[3], 0u);
  const RayKindPlan plan = plan_ray_kinds(scene, 10, RayScope::Primary);
  EXPECT_EQ(plan.why_not[1], "rays limited to primary");
  EXPECT_EQ(plan.why_not[2], "rays limited to primary");
}

TEST(RenderScopeTest, PrimaryShadowIsTheWholeRenderWithoutSecondaryRays) {
  const Scene scene = test_scenes::cornell_box();
  RenderOptions options = small_options();
  options.rays = RayScope::PrimaryShadow;
  const Rendered narrowed = render(scene, options);
  // A ray tree one deep is exactly the primary rays and their shadow rays.
  RenderOptions one_deep = small_options();
  one_deep.max_depth = 1;
  const Rendered shallow = render(scene, one_deep);
  EXPECT_TRUE(narrowed.records == shallow.records);
  EXPECT_EQ(narrowed.stats.rays, shallow.stats.rays);
  EXPECT_GT(narrowed.stats.rays[1], 0u);
  EXPECT_EQ(narrowed.stats.rays[2] + narrowed.stats.rays[3], 0u);
  // The full render casts secondary rays: the option is what removed them.
  EXPECT_GT(render(scene, small_options()).stats.rays[2], 0u);
  EXPECT_EQ(plan_ray_kinds(scene, 10, RayScope::PrimaryShadow).why_not[2], "rays limited to primary+shadow");
  EXPECT_TRUE(plan_ray_kinds(scene, 10, RayScope::PrimaryShadow).casts(RayKind::Shadow));
}

TEST(RenderScopeTest, FirstLightOnlyCastsOneShadowRayPerHitInFrontOfThatLight) {
  // Diffuse only, so every hit is a primary hit; a second light on the other side.
  Scene scene = test_scenes::cornell_box(false, false, true);
  Scene first_only_scene = scene;
  scene.lights.push_back({{0.1f, 0.3f, 1.5f}, {0.5f, 0.5f, 0.5f}});
  RenderOptions options = small_options();
  options.first_light_only = true;
  const Rendered first = render(scene, options);

  // Count the primary hits whose surface faces the first light.
  const KdTree tree = KdTree::build(scene.triangles);
  const Layout layout = make_layout(tree, LayoutKind::Hybrid, 4);
  const Renderer probe(scene, tree, layout, small_options());
  const PinholeCamera camera(*scene.camera, kWidth, kHeight);
  std::uint64_t in_front = 0;
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      const Ray ray = camera.primary_ray(x, y);
      const auto hit = probe.closest_hit(ray, kInf, nullptr, nullptr);
      if (!hit) continue;
      const Triangle& t = scene.triangles[hit->triangle];
      const Vec3 point = interpolate_surface_point(t, hit->b0, hit->u, hit->v).point;
      const Vec3 face = triangle_unit_normal(t, {0, 0, 1});
      const Vec3 facing = dot(ray.direction, face) < 0 ? face : -face;
      in_front += dot(scene.lights[0].position - point, facing) > 0;
    }
  }
  ASSERT_GT(in_front, 0u);
  EXPECT_EQ(first.stats.rays[1], in_front);
  // All lights cast more; and the render is the one of the scene with its first light alone.
  EXPECT_GT(render(scene, small_options()).stats.rays[1], in_front);
  const Rendered alone = render(first_only_scene, small_options());
  EXPECT_TRUE(first.records == alone.records);
  EXPECT_EQ(first.stats.rays, alone.stats.rays);
}

// The defaults spelled out are the defaults: the same trace, byte for byte,
// and the header names none of the new options.
TEST(RenderScopeCliTest, ExplicitDefaultsGiveTheSameTraceBytes) {
  testing::TempDir dir;
  const std::string tracer = testing::shell_quoted(testing::program("tracer"));
  const std::string base = tracer + " render mountain:6 --width 24 --height 18 -q --high-size 1k -o ";
  const auto plain = testing::run_command(base + testing::shell_quoted(dir / "plain.din.zst"));
  const auto spelled = testing::run_command(base + testing::shell_quoted(dir / "spelled.din.zst") +
                                            " --rays whitted --lights all --leaf-size 0");
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  ASSERT_EQ(spelled.exit_code, 0) << spelled.err;
  const std::string bytes = testing::read_file(dir / "plain.din.zst");
  EXPECT_TRUE(bytes == testing::read_file(dir / "spelled.din.zst"));
  const auto info = testing::run_command(tracer + " render mountain:6 --width 24 --height 18 -q --high-size 1k -o " +
                                         testing::shell_quoted(dir / "narrow.din.zst") +
                                         " --rays primary+shadow --lights first --leaf-size 3");
  ASSERT_EQ(info.exit_code, 0) << info.err;
  const auto header = testing::run_command(testing::shell_quoted(testing::program("tracetool")) +
                                           " info --format json " + testing::shell_quoted(dir / "narrow.din.zst"));
  ASSERT_EQ(header.exit_code, 0) << header.err;
  for (const std::string field : {"\"rays\": \"primary+shadow\"", "\"lights\": \"first\"", "\"leaf_size\": 3"}) {
    EXPECT_NE(header.out.find(field), std::string::npos) << field << " in " << header.out;
  }
  const auto plain_header = testing::run_command(testing::shell_quoted(testing::program("tracetool")) +
                                                 " info --format json " + testing::shell_quoted(dir / "plain.din.zst"));
  for (const std::string field : {"\"lights\"", "\"leaf_size\""}) {
    EXPECT_EQ(plain_header.out.find(field), std::string::npos) << field << " in " << plain_header.out;
  }
}

}  // namespace
}  // namespace nodetrace::tracer
