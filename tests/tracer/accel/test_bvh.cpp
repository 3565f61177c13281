// The BVHs against the kd-tree: every primary and shadow ray finds the same
// closest hit (triangle, distance within 1e-6 relative) with every structure,
// differences only exact distance ties, at most 0.01% of rays; compressed
// boxes contain the exact ones on every node; fetch records are the nodes
// visited; the build does not depend on threads.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <set>

#include "nodetrace/tracer/accel/acceleration_structure.hpp"
#include "nodetrace/tracer/render/camera.hpp"
#include "nodetrace/tracer/scene/scene_loader.hpp"
#include "test_render_scenes.hpp"
#include "test_support.hpp"

namespace nodetrace::tracer {
namespace {

// The sanitizer build runs traversals several times slower: smaller images there.
#if defined(__SANITIZE_ADDRESS__)
constexpr int kImageScale = 2;
#else
constexpr int kImageScale = 1;
#endif

constexpr AccelKind kBvhs[] = {AccelKind::Bvh2, AccelKind::Bvh4, AccelKind::Bvh8, AccelKind::CwBvh8};

struct HitComparison {
  std::uint64_t rays = 0, equal = 0, ties = 0;
  std::vector<std::string> other;  // differences that are not exact ties
};

bool same_distance(float a, float b) { return std::fabs(a - b) <= 1e-6f * std::max(std::fabs(a), std::fabs(b)); }

// Primary rays of a width x height image and, at each kd-tree hit, one
// shadow ray to each light; each traced by both structures.
HitComparison compare_hits(const Scene& scene, const AccelerationStructure& reference,
                           const AccelerationStructure& other, int width, int height) {
  const Layout ref_layout = make_layout(reference.shape(), LayoutKind::Dfl);
  const Layout other_layout = make_layout(other.shape(), LayoutKind::Dfl);
  const auto ref = reference.traversal(scene.triangles, ref_layout, {}, {});
  const auto cmp = other.traversal(scene.triangles, other_layout, {}, {});
  const Camera camera = scene.camera ? *scene.camera : default_camera(reference.bounds());
  const PinholeCamera pinhole(camera, width, height);
  HitComparison result;
  const float inf = std::numeric_limits<float>::infinity();
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const Ray ray = pinhole.primary_ray(x, y);
      Hit a, b;
      const bool ha = ref->closest_hit(ray, inf, a, nullptr, nullptr);
      const bool hb = cmp->closest_hit(ray, inf, b, nullptr, nullptr);
      ++result.rays;
      if (ha == hb && (!ha || (a.triangle == b.triangle && same_distance(a.t, b.t)))) {
        ++result.equal;
      } else if (ha && hb && a.t == b.t) {
        ++result.ties;
      } else {
        char text[160];
        std::snprintf(text, sizeof text, "primary (%d, %d): kd-tree %s t=%.9g id=%u, other %s t=%.9g id=%u", x, y,
                      ha ? "hit" : "miss", double(a.t), a.triangle, hb ? "hit" : "miss", double(b.t), b.triangle);
        result.other.push_back(text);
      }
      if (!ha) continue;
      const Vec3 p = ray.origin + ray.direction * a.t;
      for (const auto& light : scene.lights) {
        const Ray shadow{p, light.position - p};
        const bool oa = ref->any_hit(shadow, 1.0f, nullptr, nullptr);
        const bool ob = cmp->any_hit(shadow, 1.0f, nullptr, nullptr);
        ++result.rays;
        if (oa == ob) {
          ++result.equal;
        } else {
          char text[160];
          std::snprintf(text, sizeof text, "shadow from (%d, %d): kd-tree %s, other %s", x, y,
                        oa ? "occluded" : "clear", ob ? "occluded" : "clear");
          result.other.push_back(text);
        }
      }
    }
  }
  return result;
}

void expect_same_hits(const Scene& scene, int width, int height) {
  const auto kd = AccelerationStructure::build(scene.triangles, AccelKind::KdTree);
  for (const auto kind : kBvhs) {
    SCOPED_TRACE(std::string(accel_name(kind)));
    const auto bvh = AccelerationStructure::build(scene.triangles, kind);
    const HitComparison c = compare_hits(scene, kd, bvh, width, height);
    ASSERT_GT(c.rays, std::uint64_t(width) * height);  // some shadow rays were cast
    std::printf("  %s: %llu rays, %llu the same, %llu distance ties, %zu other differences\n",
                std::string(accel_name(kind)).c_str(), static_cast<unsigned long long>(c.rays),
                static_cast<unsigned long long>(c.equal), static_cast<unsigned long long>(c.ties), c.other.size());
    for (const auto& line : c.other) std::printf("  %s: %s\n", std::string(accel_name(kind)).c_str(), line.c_str());
    EXPECT_GE(double(c.equal) / double(c.rays), 0.9999) << c.ties << " ties, " << c.other.size() << " others";
    // Anything but an exact tie would be a ray lost at a grazing box edge:
    // none is allowed beyond the 0.01%.
    EXPECT_LE(double(c.other.size()), 1e-4 * double(c.rays));
  }
}

TEST(BvhTest, HitsMatchKdTreeOnBuiltInScenes) {
  for (const char* spec : {"sphereflake:1", "mountain:6", "forest:1"}) {
    SCOPED_TRACE(spec);
    const auto source = open_scene(spec);
    expect_same_hits(source->at_frame(0), 64 / kImageScale, 48 / kImageScale);
  }
}

TEST(BvhTest, HitsMatchKdTreeOnBartRobot) {
  NODETRACE_SHARED_OR_SKIP(shared);
  const auto source = open_scene((shared / "scenes/bart/robots/Robot.aff").string());
  expect_same_hits(source->at_frame(0), 40 / kImageScale, 30 / kImageScale);
}

TEST(BvhTest, HitsMatchKdTreeOnRandomTriangles) {
  Scene scene = test_scenes::random_triangles(4000, 7);
  scene.lights.push_back({{0, 30, 0}, {1, 1, 1}});
  expect_same_hits(scene, 48, 48);
}

void expect_conservative_boxes(const Bvh& bvh) {
  ASSERT_TRUE(bvh.compressed());
  ASSERT_EQ(bvh.exact_child_boxes().size(), bvh.children().size());
  for (std::size_t i = 0; i < bvh.children().size(); ++i) {
    const Bounds& q = bvh.children()[i].box;
    const Bounds& e = bvh.exact_child_boxes()[i];
    for (int a = 0; a < 3; ++a) {
      ASSERT_LE(q.lo[a], e.lo[a]) << "child " << i << " axis " << a;
      ASSERT_GE(q.hi[a], e.hi[a]) << "child " << i << " axis " << a;
    }
  }
  // And the quantization is coarse: boxes are on each node's grid.
  for (std::size_t n = 0; n < bvh.nodes().size(); ++n) {
    const BvhNode& node = bvh.nodes()[n];
    const BvhQuantization& qz = bvh.quantizations()[n];
    for (std::uint32_t k = 0; k < node.child_count; ++k) {
      const Bounds& q = bvh.children()[node.first_child + k].box;
      for (int a = 0; a < 3; ++a) {
        const double step = std::ldexp(1.0, qz.exponent[a]);
        const double steps_hi = (double(q.hi[a]) - qz.origin[a]) / step;
        ASSERT_LE(steps_hi, 255.0 * (1 + 1e-6) + 1) << "node " << n;
        ASSERT_GE((double(q.lo[a]) - qz.origin[a]) / step, -1e-6) << "node " << n;
      }
    }
  }
}

TEST(BvhTest, CompressedBoxesContainExactOnes) {
  expect_conservative_boxes(Bvh::build(test_scenes::random_triangles(5000, 3).triangles, 8, true));
  expect_conservative_boxes(Bvh::build(open_scene("mountain:6")->at_frame(0).triangles, 8, true));
}

TEST(BvhTest, CompressedBoxesContainExactOnesOnBartScenes) {
  NODETRACE_SHARED_OR_SKIP(shared);
  for (const char* path : {"scenes/bart/robots/Robot.aff", "scenes/bart/kitchen/kitchen.aff"}) {
    SCOPED_TRACE(path);
    expect_conservative_boxes(Bvh::build(open_scene((shared / path).string())->at_frame(0).triangles, 8, true));
  }
}

TEST(BvhTest, TreeShapeIsWellFormed) {
  const auto triangles = test_scenes::random_triangles(3000, 5).triangles;
  for (const unsigned arity : {2u, 4u, 8u}) {
    const Bvh bvh = Bvh::build(triangles, arity, false);
    std::vector<int> seen(triangles.size(), 0);
    std::uint64_t interior_children = 0;
    for (const auto& node : bvh.nodes()) {
      ASSERT_GE(node.child_count, 1u);
      ASSERT_LE(node.child_count, arity);
      for (std::uint32_t k = 0; k < node.child_count; ++k) {
        const BvhChild& c = bvh.children()[node.first_child + k];
        if (c.is_leaf()) {
          ASSERT_LE(c.count, BvhBuildOptions{}.max_leaf_size);
          for (std::uint32_t i = 0; i < c.count; ++i) ++seen[bvh.primitives()[c.index + i]];
        } else {
          ++interior_children;
          ASSERT_EQ(bvh.nodes()[c.index].level, node.level + 1);
        }
      }
    }
    for (const int s : seen) ASSERT_EQ(s, 1);  // every triangle in exactly one leaf
    EXPECT_EQ(interior_children + 1, bvh.nodes().size());
    EXPECT_EQ(bvh.stats().primitive_references, triangles.size());
  }
}

TEST(BvhTest, BuildIsDeterministic) {
  // Large enough that the top levels are built on threads of their own.
  const auto triangles = test_scenes::random_triangles(20000, 9).triangles;
  const Bvh a = Bvh::build(triangles, 2, false), b = Bvh::build(triangles, 2, false);
  ASSERT_EQ(a.nodes().size(), b.nodes().size());
  EXPECT_EQ(a.primitives(), b.primitives());
  for (std::size_t i = 0; i < a.children().size(); ++i) {
    ASSERT_EQ(a.children()[i].index, b.children()[i].index);
    ASSERT_EQ(a.children()[i].count, b.children()[i].count);
  }
}

TEST(BvhTest, FetchRecordsAreTheNodesVisited) {
  Scene scene = test_scenes::random_triangles(3000, 11);
  for (const auto kind : kBvhs) {
    SCOPED_TRACE(std::string(accel_name(kind)));
    const auto accel = AccelerationStructure::build(scene.triangles, kind);
    const Layout layout = make_layout(accel.shape(), LayoutKind::Bfl);
    AddressMap map;
    map.node_size = default_node_size(kind);
    map.node_base = 0x1000;
    const auto traversal = accel.traversal(scene.triangles, layout, {true, true, false}, map);
    const Bvh& bvh = *accel.bvh();
    std::vector<std::uint32_t> node_at_slot(layout.slot_of_node.size());
    for (std::uint32_t n = 0; n < node_at_slot.size(); ++n) node_at_slot[layout.slot_of_node[n]] = n;
    const PinholeCamera pinhole(default_camera(accel.bounds()), 24, 24);
    for (int p = 0; p < 24 * 24; ++p) {
      const Ray ray = pinhole.primary_ray(p % 24, p / 24);
      std::vector<formats::Record> records;
      RenderStats stats;
      Hit hit;
      traversal->closest_hit(ray, std::numeric_limits<float>::infinity(), hit, &records, &stats);
      std::uint64_t nodes = 0, lists = 0;
      std::set<std::uint32_t> children_of_visited{0};  // a fetched node is the root or a child of one fetched
      for (const auto& r : records) {
        if (r.tag == formats::kTagPrimitiveList) {
          ++lists;
          continue;
        }
        ++nodes;
        ASSERT_EQ(r.size, map.node_size);
        ASSERT_EQ((r.address - map.node_base) % map.node_size, 0u);
        const std::uint32_t n = node_at_slot.at((r.address - map.node_base) / map.node_size);
        ASSERT_EQ(r.tag, bvh.nodes()[n].level);
        ASSERT_TRUE(children_of_visited.count(n)) << "node " << n << " fetched before its parent";
        const BvhNode& node = bvh.nodes()[n];
        for (std::uint32_t k = 0; k < node.child_count; ++k) {
          const BvhChild& c = bvh.children()[node.first_child + k];
          if (!c.is_leaf()) children_of_visited.insert(c.index);
        }
      }
      ASSERT_EQ(nodes, stats.node_fetches);
      ASSERT_EQ(lists, stats.triangle_tests);
      if (!records.empty()) {
        EXPECT_EQ(records.front().address, map.node_base) << "the root, slot 0, first";
      }
    }
  }
}

TEST(BvhTest, NodeCountsShrinkWithArity) {
  const auto triangles = test_scenes::random_triangles(5000, 13).triangles;
  const Bvh b2 = Bvh::build(triangles, 2, false), b4 = Bvh::build(triangles, 4, false),
            b8 = Bvh::build(triangles, 8, false);
  // Same leaves (the collapse never changes them), fewer and shallower nodes.
  EXPECT_EQ(b2.stats().leaves, b4.stats().leaves);
  EXPECT_EQ(b2.stats().leaves, b8.stats().leaves);
  EXPECT_EQ(b2.stats().leaves, b2.stats().nodes + 1);
  EXPECT_LT(b4.stats().nodes, b2.stats().nodes);
  EXPECT_LT(b8.stats().nodes, b4.stats().nodes);
  EXPECT_LT(b8.stats().depth, b2.stats().depth);
}

}  // namespace
}  // namespace nodetrace::tracer
