// The renderer: watertight intersection, the fetch rules of docs/ARCHITECTURE.md on a
// hand-built tree, pixel orders, ray kinds, and the same records whatever the
// thread count.
#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <random>

#include "nodetrace/tracer/render/interaction.hpp"
#include "nodetrace/tracer/accel/kdtree.hpp"
#include "nodetrace/tracer/accel/layout.hpp"
#include "nodetrace/tracer/render/render.hpp"
#include "test_render_scenes.hpp"

namespace nodetrace::tracer {
namespace {

using formats::Record;
using test_scenes::uniform;
constexpr float kInf = std::numeric_limits<float>::infinity();

TEST(RenderTest, NoRayEscapesAClosedSphereFromInside) {
  const Scene sphere = test_scenes::closed_sphere(48, 96, 1.0f);
  const KdTree tree = KdTree::build(sphere.triangles);
  const Layout layout = make_layout(tree, LayoutKind::Dfl);
  const Renderer renderer(sphere, tree, layout, RenderOptions{});
  const Vec3 center{0.1f, -0.2f, 0.3f};
  std::mt19937 engine(1234);
  int escapes = 0, rehits = 0, bounce_escapes = 0;
  const int rays = 1'000'000;
  for (int i = 0; i < rays; ++i) {
    Vec3 offset;
    do {
      offset = {uniform(engine, -1, 1), uniform(engine, -1, 1), uniform(engine, -1, 1)};
    } while (dot(offset, offset) > 0.95f * 0.95f);
    Vec3 direction;
    do {
      direction = {uniform(engine, -1, 1), uniform(engine, -1, 1), uniform(engine, -1, 1)};
    } while (dot(direction, direction) < 1e-4f);
    const Ray ray{center + offset, normalize(direction)};
    const auto hit = renderer.closest_hit(ray, kInf, nullptr, nullptr);
    if (!hit) {
      ++escapes;
      continue;
    }
    if (i % 4 != 0) continue;
    // Bounce inwards from the hit point: the mirror ray must stay inside and
    // must not find its own triangle again.
    const Triangle& t = sphere.triangles[hit->triangle];
    const SurfacePoint point = interpolate_surface_point(t, hit->b0, hit->u, hit->v);
    Vec3 normal = normalize(cross(t.v1 - t.v0, t.v2 - t.v0));
    if (dot(normal, ray.direction) > 0) normal = -normal;
    const Vec3 reflected = ray.direction - normal * (2 * dot(ray.direction, normal));
    const Ray bounce{offset_ray_origin(point, normal), normalize(reflected)};
    const auto second = renderer.closest_hit(bounce, kInf, nullptr, nullptr);
    if (!second) {
      ++bounce_escapes;
    } else if (second->triangle == hit->triangle) {
      ++rehits;
    }
  }
  EXPECT_EQ(escapes, 0);
  EXPECT_EQ(bounce_escapes, 0);
  EXPECT_EQ(rehits, 0);
}

TEST(RenderTest, WatertightTestHitsASharedEdgeExactlyOnce) {
  // Two triangles sharing the edge x = 0; rays straight through the edge.
  const Triangle left{{0, -1, 0}, {0, 1, 0}, {-1, 0, 0}, 0};
  const Triangle right{{0, -1, 0}, {1, 0, 0}, {0, 1, 0}, 0};
  for (float y : {-0.5f, 0.0f, 0.25f, 0.7f}) {
    const Ray ray{{0, y, 5}, {0, 0, -1}};
    const int hits = int(intersect_triangle(ray, left, kInf).has_value()) +
                     int(intersect_triangle(ray, right, kInf).has_value());
    EXPECT_EQ(hits, 1) << "y = " << y;
  }
  // A hit behind the origin or beyond t_max is no hit.
  EXPECT_FALSE(intersect_triangle({{-0.2f, 0, 5}, {0, 0, 1}}, left, kInf).has_value());
  EXPECT_FALSE(intersect_triangle({{-0.2f, 0, 5}, {0, 0, -1}}, left, 4.0f).has_value());
  const auto h = intersect_triangle({{-0.2f, 0, 5}, {0, 0, -1}}, left, kInf);
  ASSERT_TRUE(h.has_value());
  EXPECT_FLOAT_EQ(h->t, 5.0f);
}

// Root splits x at 0: left leaf {A} (x = -1); right interior splits x at 1:
// an empty leaf, then leaf {B} (x = 1.5). Indices are pre-order.
struct TinyWorld {
  Scene scene;
  KdTree tree;
};

TinyWorld tiny_world() {
  TinyWorld w;
  w.scene.materials.push_back({});
  w.scene.triangles.push_back({{-1, -1, -1}, {-1, 3, -1}, {-1, -1, 3}, 0});   // A
  w.scene.triangles.push_back({{1.5f, -1, -1}, {1.5f, 9, -1}, {1.5f, -1, 9}, 0});  // B
  std::vector<KdNode> nodes(5);
  nodes[0] = {0.0f, 1, 2, 0, 0, 0, 0};
  nodes[1] = {0, 0, 0, 0, 1, 1, KdNode::kLeafAxis};
  nodes[2] = {1.0f, 3, 4, 0, 0, 1, 0};
  nodes[3] = {0, 0, 0, 1, 0, 2, KdNode::kLeafAxis};
  nodes[4] = {0, 0, 0, 1, 1, 2, KdNode::kLeafAxis};
  w.tree = KdTree::from_nodes(std::move(nodes), {0, 1}, w.scene.bounds());
  return w;
}

std::vector<std::pair<std::uint64_t, formats::Tag>> address_and_tag(const std::vector<Record>& records) {
  std::vector<std::pair<std::uint64_t, formats::Tag>> out;
  for (const auto& r : records) {
    EXPECT_EQ(r.type, formats::AccessType::Read);
    out.emplace_back(r.address, r.tag);
  }
  return out;
}

TEST(RenderTest, TraversalFetchesEachVisitedNodeOnceInVisitOrder) {
  const TinyWorld w = tiny_world();
  RenderOptions options;
  options.addresses.node_base = 0x1000;
  options.addresses.node_size = 8;
  const Layout layout = make_layout(w.tree, LayoutKind::Dfl);
  const Renderer renderer(w.scene, w.tree, layout, options);
  using Fetches = std::vector<std::pair<std::uint64_t, formats::Tag>>;

  std::vector<Record> records;
  RenderStats stats;
  // Hits A in the first leaf: the pushed right child is never read.
  auto hit = renderer.closest_hit({{-2, 0, 0}, {1, 0, 0}}, kInf, &records, &stats);
  ASSERT_TRUE(hit);
  EXPECT_EQ(hit->triangle, 0u);
  EXPECT_EQ(address_and_tag(records), (Fetches{{0x1000, 0}, {0x1008, 1}}));
  for (const auto& r : records) EXPECT_EQ(r.size, 8u);
  EXPECT_EQ(stats.node_fetches, 2u);
  EXPECT_EQ(stats.leaf_visits, 1u);
  EXPECT_EQ(stats.triangle_tests, 1u);

  // Misses A: pops the right child, walks the empty leaf, then hits B.
  records.clear();
  hit = renderer.closest_hit({{-2, 2.5f, 2.5f}, {1, 0, 0}}, kInf, &records, nullptr);
  ASSERT_TRUE(hit);
  EXPECT_EQ(hit->triangle, 1u);
  EXPECT_EQ(address_and_tag(records),
            (Fetches{{0x1000, 0}, {0x1008, 1}, {0x1010, 1}, {0x1018, 2}, {0x1020, 2}}));

  // From the other side: far-to-near order, stops in the first leaf.
  records.clear();
  hit = renderer.closest_hit({{3, 0, 0}, {-1, 0, 0}}, kInf, &records, nullptr);
  ASSERT_TRUE(hit);
  EXPECT_EQ(hit->triangle, 1u);
  EXPECT_EQ(address_and_tag(records), (Fetches{{0x1000, 0}, {0x1010, 1}, {0x1020, 2}}));

  // Any-hit shadow ray that stops short of B reads only the nodes it reaches.
  records.clear();
  EXPECT_FALSE(renderer.occluded({{0.5f, 0, 0}, {1, 0, 0}}, 0.4f, &records, nullptr));
  EXPECT_EQ(address_and_tag(records), (Fetches{{0x1000, 0}, {0x1010, 1}, {0x1018, 2}}));

  // A ray missing the scene box reads nothing.
  records.clear();
  EXPECT_FALSE(renderer.closest_hit({{-2, 50, 0}, {1, 0, 0}}, kInf, &records, nullptr));
  EXPECT_TRUE(records.empty());
}

TEST(RenderTest, AddressesFollowTheLayoutAndOptionalStreams) {
  const TinyWorld w = tiny_world();
  RenderOptions options;
  options.addresses.node_base = 0;
  options.addresses.node_size = 16;
  options.streams.lists = true;
  options.streams.triangles = true;
  Layout reversed;
  reversed.slot_of_node = {4, 3, 2, 1, 0};
  const Renderer renderer(w.scene, w.tree, reversed, options);
  std::vector<Record> records;
  ASSERT_TRUE(renderer.closest_hit({{-2, 0, 0}, {1, 0, 0}}, kInf, &records, nullptr));
  ASSERT_EQ(records.size(), 4u);
  EXPECT_EQ(records[0].address, 4u * 16);
  EXPECT_EQ(records[0].size, 16u);
  EXPECT_EQ(records[1].address, 3u * 16);
  EXPECT_EQ(records[1].tag, 1);
  EXPECT_EQ(records[2].address, options.addresses.list_base);
  EXPECT_EQ(records[2].tag, formats::kTagPrimitiveList);
  EXPECT_EQ(records[3].address, options.addresses.triangle_base);
  EXPECT_EQ(records[3].size, 36u);
  EXPECT_EQ(records[3].tag, formats::kTagTriangle);
}

TEST(RenderTest, PixelOrdersArePermutations) {
  for (auto order : {PixelOrder::Scanline, PixelOrder::Tiled, PixelOrder::Morton}) {
    auto sequence = pixel_sequence(37, 21, order, 8);
    ASSERT_EQ(sequence.size(), 37u * 21u);
    std::vector<std::uint32_t> sorted = sequence;
    std::sort(sorted.begin(), sorted.end());
    for (std::uint32_t i = 0; i < sorted.size(); ++i) ASSERT_EQ(sorted[i], i);
  }
  const auto morton = pixel_sequence(4, 4, PixelOrder::Morton, 8);
  EXPECT_EQ(std::vector<std::uint32_t>(morton.begin(), morton.begin() + 5),
            (std::vector<std::uint32_t>{0, 1, 4, 5, 2}));
  const auto tiled = pixel_sequence(4, 4, PixelOrder::Tiled, 2);
  EXPECT_EQ(std::vector<std::uint32_t>(tiled.begin(), tiled.begin() + 5),
            (std::vector<std::uint32_t>{0, 1, 4, 5, 2}));
  EXPECT_EQ(parse_pixel_order("morton"), PixelOrder::Morton);
  EXPECT_FALSE(parse_pixel_order("spiral"));
}

std::vector<Record> render_records(const Scene& scene, RenderOptions options, RenderStats* stats,
                                   Image* image = nullptr) {
  const KdTree tree = KdTree::build(scene.triangles);
  const Layout layout = make_layout(tree, LayoutKind::Hybrid, 4);
  const Renderer renderer(scene, tree, layout, options);
  std::vector<Record> all;
  *stats = renderer.render([&](std::span<const Record> r) { all.insert(all.end(), r.begin(), r.end()); },
                           image);
  return all;
}

TEST(RenderTest, SameRecordsWhateverTheThreadCount) {
  const Scene scene = test_scenes::cornell_box();
  RenderOptions options;
  options.width = 64;
  options.height = 48;
  options.pixels_per_chunk = 7;
  for (auto order : {PixelOrder::Scanline, PixelOrder::Morton}) {
    options.pixel_order = order;
    options.threads = 1;
    RenderStats one, two, three;
    Image image_one, image_two;
    const auto a = render_records(scene, options, &one, &image_one);
    options.threads = 2;
    const auto b = render_records(scene, options, &two, &image_two);
    options.threads = 3;
    options.pixels_per_chunk = 100;
    const auto c = render_records(scene, options, &three);
    options.pixels_per_chunk = 7;
    ASSERT_GT(a.size(), 64u * 48u);
    EXPECT_TRUE(a == b);
    EXPECT_TRUE(a == c);
    EXPECT_EQ(one.rays, two.rays);
    EXPECT_EQ(one.records, a.size());
    EXPECT_TRUE(image_one.pixels == image_two.pixels);
  }
}

TEST(RenderTest, TimesOneRayInKTimeEveryOfEachKindAndTheWorkersCpu) {
  // The summary's rays per core-second: every kind cast has timed rays (one
  // in kTimeEvery, the first of each kind in each chunk included), never
  // more than it cast. That the records do not depend on it, the pinned
  // trace hashes check.
  const Scene scene = test_scenes::cornell_box();
  RenderOptions options;
  options.width = 32;
  options.height = 24;
  options.threads = 2;
  RenderStats stats;
  render_records(scene, options, &stats);
  EXPECT_GT(stats.cpu_seconds, 0.0);
  for (int k = 0; k < 4; ++k) {
    const auto kind = static_cast<RayKind>(k);
    ASSERT_GT(stats.rays[k], 0u) << ray_kind_name(kind);
    EXPECT_GT(stats.timed_rays[k], 0u) << ray_kind_name(kind);
    EXPECT_LE(stats.timed_rays[k], stats.rays[k]) << ray_kind_name(kind);
    EXPECT_GT(stats.traversal_rays_per_second(kind), 0.0) << ray_kind_name(kind);
  }
  EXPECT_EQ(stats.traversal_rays_per_second(RayKind::Diffuse), 0.0);  // Whitted casts none
}

TEST(RenderTest, CastsOnlyTheRayKindsTheSceneNeeds) {
  RenderOptions options;
  options.width = 40;
  options.height = 30;
  options.threads = 2;
  RenderStats stats;

  const Scene dark = test_scenes::cornell_box(false, false, false);
  const RayKindPlan dark_plan = plan_ray_kinds(dark, 10);
  EXPECT_FALSE(dark_plan.casts(RayKind::Shadow));
  EXPECT_EQ(dark_plan.why_not[1], "scene has no light");
  EXPECT_EQ(dark_plan.why_not[3], "no material transmits");
  render_records(dark, options, &stats);
  EXPECT_EQ(stats.rays[0], 40u * 30u);
  EXPECT_EQ(stats.rays[1] + stats.rays[2] + stats.rays[3], 0u);

  render_records(test_scenes::cornell_box(false, false, true), options, &stats);
  EXPECT_GT(stats.rays[1], 0u);
  EXPECT_EQ(stats.rays[2] + stats.rays[3], 0u);

  // Glass alone reflects too (Fresnel, total internal reflection).
  render_records(test_scenes::cornell_box(false, true, true), options, &stats);
  EXPECT_GT(stats.rays[2], 0u);
  EXPECT_GT(stats.rays[3], 0u);

  // max_depth 1: primary and shadow rays only.
  options.max_depth = 1;
  render_records(test_scenes::cornell_box(true, true, true), options, &stats);
  EXPECT_GT(stats.rays[1], 0u);
  EXPECT_EQ(stats.rays[2] + stats.rays[3], 0u);
  EXPECT_EQ(plan_ray_kinds(test_scenes::cornell_box(), 1).why_not[2], "max_depth is 1");
}

TEST(RenderTest, MirrorRecursionStopsAtMaxDepth) {
  // Two facing mirrors: a ray between them bounces until max_depth.
  Scene scene;
  Material mirror;
  mirror.reflectance = 1.0f;
  scene.materials = {mirror};
  test_scenes::add_quad(scene, {-5, -5, 0}, {5, -5, 0}, {5, 5, 0}, {-5, 5, 0}, 0);
  test_scenes::add_quad(scene, {-5, -5, 1}, {-5, 5, 1}, {5, 5, 1}, {5, -5, 1}, 0);
  scene.camera = Camera{{0, 0, 0.5f}, {0, 0, 0}, {0, 1, 0}, 1.0f};
  RenderOptions options;
  options.width = 1;
  options.height = 1;
  options.max_depth = 7;
  RenderStats stats;
  render_records(scene, options, &stats);
  EXPECT_EQ(stats.rays[0], 1u);
  EXPECT_EQ(stats.rays[2], 6u);
}

}  // namespace
}  // namespace nodetrace::tracer
