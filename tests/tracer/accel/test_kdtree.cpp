// kd-tree invariants: leaves hold every triangle that overlaps them, traversal
// finds what brute force finds, statistics add up, builds are deterministic.
#include <gtest/gtest.h>

#include <cmath>
#include <initializer_list>
#include <limits>
#include <random>

#include "nodetrace/tracer/accel/kdtree.hpp"
#include "nodetrace/tracer/accel/layout.hpp"
#include "nodetrace/tracer/render/render.hpp"
#include "nodetrace/tracer/scene/scene_loader.hpp"
#include "test_render_scenes.hpp"

namespace nodetrace::tracer {
namespace {

using test_scenes::uniform;

// Visits every leaf with its box.
template <typename F>
void for_each_leaf(const KdTree& tree, F&& visit) {
  struct Item {
    std::uint32_t node;
    Bounds box;
  };
  std::vector<Item> stack{{0, tree.bounds()}};
  while (!stack.empty()) {
    const Item item = stack.back();
    stack.pop_back();
    const KdNode& node = tree.nodes()[item.node];
    if (node.is_leaf()) {
      visit(node, item.box);
      continue;
    }
    Bounds left = item.box, right = item.box;
    left.hi[node.axis] = node.split;
    right.lo[node.axis] = node.split;
    stack.push_back({node.right, right});
    stack.push_back({node.left, left});
  }
}

TEST(KdTreeTest, EveryTriangleIsInEveryLeafItOverlaps) {
  const Scene scene = test_scenes::random_triangles(400, 7, 5.0f, 1.5f);
  const KdTree tree = KdTree::build(scene.triangles);
  ASSERT_GT(tree.stats().leaves, 50u);
  std::size_t checked = 0;
  for_each_leaf(tree, [&](const KdNode& leaf, const Bounds& box) {
    std::vector<bool> in_leaf(scene.triangles.size(), false);
    for (std::uint32_t i = 0; i < leaf.count; ++i) in_leaf[tree.primitives()[leaf.first + i]] = true;
    for (std::uint32_t id = 0; id < scene.triangles.size(); ++id) {
      const Bounds clipped = clip_triangle_to_box(scene.triangles[id], box);
      if (clipped.empty()) continue;
      // Touching only a face of the leaf is not overlapping it; neither is a
      // sliver of a few ulps left by rounding in the clipping.
      constexpr float kSliver = 1e-4f;
      bool on_face = false;
      for (int axis = 0; axis < 3; ++axis) {
        on_face = on_face || clipped.hi[axis] <= box.lo[axis] + kSliver ||
                  clipped.lo[axis] >= box.hi[axis] - kSliver;
      }
      if (on_face) continue;
      ++checked;
      EXPECT_TRUE(in_leaf[id]) << "triangle " << id << " overlaps a leaf that does not list it: clipped "
                               << clipped.lo.x << "," << clipped.lo.y << "," << clipped.lo.z << " - "
                               << clipped.hi.x << "," << clipped.hi.y << "," << clipped.hi.z << " leaf "
                               << box.lo.x << "," << box.lo.y << "," << box.lo.z << " - " << box.hi.x
                               << "," << box.hi.y << "," << box.hi.z;
    }
  });
  EXPECT_GT(checked, scene.triangles.size());
}

TEST(KdTreeTest, HitsEqualBruteForceOnRandomRays) {
  const Scene scene = test_scenes::random_triangles(3000, 11, 10.0f, 1.0f);
  const KdTree tree = KdTree::build(scene.triangles);
  const Layout layout = make_layout(tree, LayoutKind::Dfl);
  const Renderer renderer(scene, tree, layout, RenderOptions{});
  std::mt19937 engine(5);
  int hits = 0;
  for (int i = 0; i < 4000; ++i) {
    const Vec3 origin{uniform(engine, -14, 14), uniform(engine, -14, 14), uniform(engine, -14, 14)};
    const Vec3 direction = normalize(Vec3{uniform(engine, -1, 1), uniform(engine, -1, 1), uniform(engine, -1, 1)});
    const Ray ray{origin, direction};
    float best = std::numeric_limits<float>::infinity();
    for (const auto& t : scene.triangles) {
      if (auto h = intersect_triangle(ray, t, best)) best = h->t;
    }
    const auto hit = renderer.closest_hit(ray, std::numeric_limits<float>::infinity(), nullptr, nullptr);
    if (std::isinf(best)) {
      EXPECT_FALSE(hit.has_value()) << "ray " << i;
    } else {
      ASSERT_TRUE(hit.has_value()) << "ray " << i;
      EXPECT_EQ(hit->t, best) << "ray " << i;
      ++hits;
    }
    EXPECT_EQ(renderer.occluded(ray, 1e30f, nullptr, nullptr), !std::isinf(best)) << "ray " << i;
  }
  EXPECT_GT(hits, 1000);
}

TEST(KdTreeTest, StatisticsAddUp) {
  const Scene scene = test_scenes::random_triangles(5000, 3);
  const KdTree tree = KdTree::build(scene.triangles);
  const KdTreeStats& s = tree.stats();
  EXPECT_EQ(s.nodes, tree.nodes().size());
  EXPECT_EQ(s.interior + s.leaves, s.nodes);
  EXPECT_EQ(s.leaves, s.interior + 1);  // a full binary tree
  std::uint64_t sum = 0;
  for (auto n : s.nodes_per_level) sum += n;
  EXPECT_EQ(sum, s.nodes);
  EXPECT_EQ(s.nodes_per_level.size(), s.depth + 1u);
  EXPECT_EQ(s.nodes_per_level[0], 1u);
  EXPECT_LE(static_cast<int>(s.depth), default_max_depth(5000));
  EXPECT_EQ(s.depth_limit, default_max_depth(5000));
  EXPECT_EQ(s.primitive_references, tree.primitives().size());
  EXPECT_GE(s.primitive_references, scene.triangles.size());
  EXPECT_GT(s.empty_leaves, 0u);  // the empty-space bonus cuts off empty space
  EXPECT_GT(s.sah_cost, 0.0);
  EXPECT_LT(s.sah_cost, 1.5 * 5000);  // far better than one leaf of everything
  // Children are one level below their parent, and left follows its parent.
  for (std::uint32_t i = 0; i < tree.nodes().size(); ++i) {
    const KdNode& n = tree.nodes()[i];
    if (n.is_leaf()) continue;
    EXPECT_EQ(n.left, i + 1);
    EXPECT_EQ(tree.nodes()[n.left].level, n.level + 1);
    EXPECT_EQ(tree.nodes()[n.right].level, n.level + 1);
  }
}

TEST(KdTreeTest, BuildIsDeterministic) {
  const Scene scene = test_scenes::random_triangles(2000, 9);
  const KdTree a = KdTree::build(scene.triangles);
  const KdTree b = KdTree::build(scene.triangles);
  ASSERT_EQ(a.nodes().size(), b.nodes().size());
  for (std::size_t i = 0; i < a.nodes().size(); ++i) {
    EXPECT_EQ(a.nodes()[i].axis, b.nodes()[i].axis);
    EXPECT_EQ(a.nodes()[i].split, b.nodes()[i].split);
    EXPECT_EQ(a.nodes()[i].count, b.nodes()[i].count);
  }
  EXPECT_EQ(a.primitives(), b.primitives());
}

// FNV-1a 64 over every node field and the leaves' triangle lists.
std::uint64_t tree_hash(const KdTree& tree) {
  std::uint64_t hash = 1469598103934665603ull;
  auto mix = [&](const void* data, std::size_t size) {
    for (std::size_t i = 0; i < size; ++i) {
      hash ^= static_cast<const unsigned char*>(data)[i];
      hash *= 1099511628211ull;
    }
  };
  for (const KdNode& n : tree.nodes()) {
    mix(&n.split, 4), mix(&n.left, 4), mix(&n.right, 4), mix(&n.first, 4), mix(&n.count, 4);
    mix(&n.level, 2), mix(&n.axis, 1);
  }
  mix(tree.primitives().data(), tree.primitives().size() * 4);
  return hash;
}

// The tree built by one thread, after checking that each of `thread_counts` builds the same.
KdTree expect_the_same_tree_at(const Scene& scene, std::initializer_list<unsigned> thread_counts) {
  KdBuildOptions one;
  one.threads = 1;
  KdTree reference = KdTree::build(scene.triangles, one);
  for (unsigned threads : thread_counts) {
    KdBuildOptions options;
    options.threads = threads;
    const KdTree tree = KdTree::build(scene.triangles, options);
    EXPECT_EQ(tree_hash(tree), tree_hash(reference)) << threads << " threads";
    EXPECT_EQ(tree.stats().sah_cost, reference.stats().sah_cost) << threads << " threads";
  }
  return reference;
}

TEST(KdTreeTest, TreeIsTheSameForAnyThreadCount) {
  // Enough triangles that subtrees go to threads of their own.
  const Scene scene = test_scenes::random_triangles(15000, 5);
  const KdTree reference = expect_the_same_tree_at(scene, {2u, 3u, 5u, 8u});
  EXPECT_GT(reference.nodes().size(), 5000u);
}

TEST(KdTreeTest, AxesSweptApartBreakTiesLikeOneSweep) {
  // Small triangles on an integer grid in a cube, each with its two cyclic
  // axis permutations: every plane costs exactly what the same plane on the
  // other axes costs. Over 32768 triangles, the root's axes are swept on
  // threads of their own; the serial sweep keeps the first axis among equals.
  std::mt19937 engine(25);
  std::uniform_int_distribution<int> cell(0, 62), step(0, 2);
  auto grid_point = [&](Vec3 base) {
    return base + Vec3{float(step(engine)), float(step(engine)), float(step(engine))};
  };
  Scene scene;
  scene.materials.push_back({});
  auto add_with_permutations = [&](const Triangle& t) {
    auto rotate = [](const Vec3& v) { return Vec3{v.y, v.z, v.x}; };
    Triangle u = t;
    for (int turn = 0; turn < 3; ++turn) {
      scene.triangles.push_back(u);
      u.v0 = rotate(u.v0), u.v1 = rotate(u.v1), u.v2 = rotate(u.v2);
    }
  };
  Triangle diagonal;  // spans the cube, so its box is the root box
  diagonal.v0 = {0, 0, 0}, diagonal.v1 = {64, 64, 64}, diagonal.v2 = {0, 64, 0};
  add_with_permutations(diagonal);
  while (scene.triangles.size() < 36000) {
    const Vec3 base{float(cell(engine)), float(cell(engine)), float(cell(engine))};
    Triangle t;
    t.v0 = grid_point(base), t.v1 = grid_point(base), t.v2 = grid_point(base);
    add_with_permutations(t);
  }
  const KdTree reference = expect_the_same_tree_at(scene, {2u, 3u});
  ASSERT_FALSE(reference.nodes()[0].is_leaf());
  EXPECT_EQ(reference.nodes()[0].axis, 0);
}

TEST(KdTreeTest, BuiltInMountainTreeIsTheOneTracesWereRecordedWith) {
  // The hash of the tree the event-sweep build of 2026-12-02 made: a faster
  // build must make the very same tree, or traces change.
  const Scene scene = open_scene("mountain")->at_frame(0);
  EXPECT_EQ(tree_hash(KdTree::build(scene.triangles)), 0x002c8cf2868b36c6u);
}

TEST(KdTreeTest, EmptySceneIsOneEmptyLeaf) {
  const KdTree tree = KdTree::build({});
  ASSERT_EQ(tree.nodes().size(), 1u);
  EXPECT_TRUE(tree.nodes()[0].is_leaf());
  EXPECT_EQ(tree.stats().empty_leaves, 1u);
  EXPECT_TRUE(tree.bounds().empty());
}

TEST(KdTreeTest, DepthLimitIsHonoured) {
  const Scene scene = test_scenes::random_triangles(2000, 4);
  KdBuildOptions options;
  options.max_depth = 5;
  const KdTree tree = KdTree::build(scene.triangles, options);
  EXPECT_EQ(tree.stats().depth, 5u);
  EXPECT_EQ(default_max_depth(1u << 10), 8 + 13);
}

TEST(KdTreeTest, ClippingEndsExactlyOnTheBoxFace) {
  const Triangle t{{-1, -1, 0}, {3, -1, 0}, {-1, 3, 0}, 0};
  Bounds box;
  box.lo = {0, 0, -1};
  box.hi = {0.5f, 0.5f, 1};
  const Bounds c = clip_triangle_to_box(t, box);
  ASSERT_FALSE(c.empty());
  EXPECT_EQ(c.lo.x, 0.0f);
  EXPECT_EQ(c.hi.x, 0.5f);
  EXPECT_EQ(c.lo.z, 0.0f);
  EXPECT_EQ(c.hi.z, 0.0f);
  Bounds away;
  away.lo = {5, 5, -1};
  away.hi = {6, 6, 1};
  EXPECT_TRUE(clip_triangle_to_box(t, away).empty());
}

}  // namespace
}  // namespace nodetrace::tracer
