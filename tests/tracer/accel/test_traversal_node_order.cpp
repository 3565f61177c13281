// The kd-tree walk picks a ray's near child from the direction's sign; its
// node sequence, leaf visits, triangle tests and hits must be those of the
// origin-side rule it replaced (traces are the product). A copy of that
// walk, kept here as the reference, is compared record by record on
// adversarial rays: origins exactly on split planes, zero, signed-zero and
// subnormal direction components, axis-aligned rays.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "accel/box_test.hpp"
#include "accel/leaf_visit.hpp"
#include "nodetrace/tracer/accel/kdtree.hpp"
#include "nodetrace/tracer/accel/layout.hpp"
#include "nodetrace/tracer/accel/traversal.hpp"
#include "test_render_scenes.hpp"

namespace nodetrace::tracer {
namespace {

using formats::Record;

// The walk as it was before the sign-based near child: each interior step
// compares the origin with the split.
class ReferenceWalk {
 public:
  ReferenceWalk(const std::vector<Triangle>& triangles, const KdTree& tree, const Layout& layout,
                const StreamSelection& streams, const AddressMap& map)
      : listed_(detail::triangles_in_list_order(triangles, tree.primitives())),
        tree_(tree),
        layout_(layout),
        streams_(streams),
        map_(map) {}

  bool walk(const Ray& ray, float t_max, bool any_hit, Hit& hit, std::vector<Record>& records) const {
    const auto& nodes = tree_.nodes();
    const auto finite = [](const Vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); };
    if (!finite(ray.origin) || !finite(ray.direction) || ray.direction == Vec3{}) return false;
    const Vec3 inverse{1.0f / ray.direction.x, 1.0f / ray.direction.y, 1.0f / ray.direction.z};
    float t_min = 0, t_far = t_max;
    if (!detail::intersect_box(tree_.bounds(), ray.origin, inverse, t_min, t_far)) return false;
    const detail::ShearedRay sheared(ray);
    const detail::LeafVisit leaf{listed_, tree_.primitives(), sheared, streams_, map_, &records};
    struct Pending {
      std::uint32_t node;
      float t_min, t_max;
    };
    std::vector<Pending> stack;
    std::uint32_t index = 0;
    float best = t_max;
    bool found = false;
    std::uint64_t tests = 0;
    while (true) {
      const KdNode& node = nodes[index];
      records.push_back({.address = map_.node_base + std::uint64_t{layout_.slot_of_node[index]} * map_.node_size,
                         .size = map_.node_size,
                         .type = formats::AccessType::Read,
                         .tag = static_cast<formats::Tag>(node.level)});
      if (!node.is_leaf()) {
        const float o = ray.origin[node.axis];
        const float t_split = (node.split - o) * inverse[node.axis];
        const bool below_first = o < node.split || (o == node.split && ray.direction[node.axis] <= 0);
        const std::uint32_t first = below_first ? node.left : node.right;
        const std::uint32_t second = below_first ? node.right : node.left;
        if (t_split > t_far || t_split <= 0) {
          index = first;
        } else if (t_split < t_min) {
          index = second;
        } else {
          stack.push_back({second, t_split, t_far});
          index = first;
          t_far = t_split;
        }
        continue;
      }
      // The plain walk tests every listed triangle, each time it is listed.
      detail::NoTestedTriangles every_time;
      const bool hit_here =
          any_hit ? leaf.visit<true>(node.first, node.count, best, hit, tests, every_time)
                  : leaf.visit<false>(node.first, node.count, best, hit, tests, every_time);
      if (hit_here) found = true;
      if (any_hit && found) break;
      if (found && best <= t_far) break;
      if (stack.empty()) break;
      const Pending next = stack.back();
      stack.pop_back();
      if (found && best < next.t_min) break;
      index = next.node;
      t_min = next.t_min;
      t_far = next.t_max;
    }
    return found;
  }

 private:
  std::vector<Triangle> listed_;
  const KdTree& tree_;
  const Layout& layout_;
  StreamSelection streams_;
  AddressMap map_;
};

// Adversarial rays for a tree: origins moved onto split planes, directions
// with zero, negative-zero, subnormal and huge components, axis-aligned.
std::vector<Ray> adversarial_rays(const KdTree& tree, std::uint32_t seed, int count) {
  std::mt19937 engine(seed);
  const Bounds box = tree.bounds();
  std::vector<float> splits[3];
  for (const KdNode& n : tree.nodes()) {
    if (!n.is_leaf()) splits[n.axis].push_back(n.split);
  }
  const float specials[] = {0.0f, -0.0f, std::numeric_limits<float>::denorm_min(),
                            -std::numeric_limits<float>::denorm_min(), 1e-30f, -1e-30f, 1.0f, -1.0f, 1e30f};
  auto pick_split = [&](int axis) {
    const auto& s = splits[axis];
    return s.empty() ? 0.0f : s[engine() % s.size()];
  };
  std::vector<Ray> rays;
  for (int i = 0; i < count; ++i) {
    Vec3 origin, direction;
    for (int a = 0; a < 3; ++a) {
      const float lo = box.lo[a], hi = box.hi[a], pad = 0.2f * (hi - lo);
      origin[a] = test_scenes::uniform(engine, lo - pad, hi + pad);
      // Often exactly on a split plane of this axis, the rule's tie.
      if (engine() % 3 == 0) origin[a] = pick_split(a);
      direction[a] = test_scenes::uniform(engine, -1, 1);
      if (engine() % 3 == 0) direction[a] = specials[engine() % std::size(specials)];
    }
    if (engine() % 5 == 0) {  // axis-aligned, either way
      const int a = static_cast<int>(engine() % 3);
      direction = Vec3{};
      direction[a] = engine() % 2 ? 1.0f : -1.0f;
      if (engine() % 2) direction[(a + 1) % 3] = -0.0f;
    }
    rays.push_back({origin, direction});
  }
  return rays;
}

// The walk under test and the reference over one tree; not movable (the
// walks keep references to the tree and layout).
struct BothWalks {
  BothWalks(const Scene& scene, const StreamSelection& streams)
      : tree(KdTree::build(scene.triangles)),
        layout(make_layout(tree, LayoutKind::Dfl)),
        traversal(scene.triangles, tree, layout, streams, AddressMap{}),
        reference(scene.triangles, tree, layout, streams, AddressMap{}) {}
  BothWalks(const BothWalks&) = delete;
  BothWalks& operator=(const BothWalks&) = delete;

  // Compares one ray's records, answer and hit; returns whether it hit.
  bool expect_same(const Ray& ray, float t_max, bool any) const {
    std::vector<Record> got, want;
    Hit hit_got, hit_want;
    const bool found_got = any ? traversal.any_hit(ray, t_max, &got, nullptr)
                               : traversal.closest_hit(ray, t_max, hit_got, &got, nullptr);
    const bool found_want = reference.walk(ray, t_max, any, hit_want, want);
    SCOPED_TRACE(::testing::Message() << "origin " << ray.origin.x << "," << ray.origin.y << "," << ray.origin.z
                                      << " direction " << ray.direction.x << "," << ray.direction.y << ","
                                      << ray.direction.z << " t_max " << t_max << " any " << any);
    EXPECT_EQ(found_got, found_want);
    EXPECT_EQ(got, want);
    if (found_got && found_want && !any) {
      EXPECT_EQ(hit_got.t, hit_want.t);
      EXPECT_EQ(hit_got.triangle, hit_want.triangle);
      EXPECT_EQ(hit_got.u, hit_want.u);
      EXPECT_EQ(hit_got.v, hit_want.v);
      EXPECT_EQ(hit_got.b0, hit_want.b0);
    }
    return found_got;
  }

  KdTree tree;
  Layout layout;
  Traversal traversal;
  ReferenceWalk reference;
};

void expect_same_walks(const Scene& scene, std::uint32_t seed, int count) {
  const BothWalks walks(scene, StreamSelection{.nodes = true, .lists = true, .triangles = true});
  const float limits[] = {std::numeric_limits<float>::infinity(), 3.0f, 1.0f - 1e-4f};
  int hits = 0;
  for (const Ray& ray : adversarial_rays(walks.tree, seed, count)) {
    for (const float t_max : limits) {
      for (const bool any : {false, true}) {
        if (walks.expect_same(ray, t_max, any)) ++hits;
      }
    }
    if (::testing::Test::HasFailure()) return;  // one ray's report is enough
  }
  EXPECT_GT(hits, 0);
}

// The fast walk skips a triangle it tested in an earlier leaf (the walks
// above hold its hits, records and test counts to the plain walk's); what
// it remembers is the last eight ids.
TEST(TraversalNodeOrderTest, TestedTrianglesRememberTheLastEightIds) {
  detail::TestedTriangles tested;
  EXPECT_FALSE(tested.contains(0));
  EXPECT_FALSE(tested.contains(~std::uint32_t{0} - 1));
  for (std::uint32_t id = 100; id < 110; ++id) tested.add(id);
  for (std::uint32_t id = 100; id < 102; ++id) EXPECT_FALSE(tested.contains(id)) << id;
  for (std::uint32_t id = 102; id < 110; ++id) EXPECT_TRUE(tested.contains(id)) << id;
  EXPECT_FALSE(tested.contains(110));
}

TEST(TraversalNodeOrderTest, RandomTrianglesMatchOriginSideWalk) {
  expect_same_walks(test_scenes::random_triangles(2000, 7, 10.0f, 1.0f), 3, 3000);
}

// Axis-aligned walls: splits lie on the walls, and so do many origins.
TEST(TraversalNodeOrderTest, CornellBoxMatchesOriginSideWalk) {
  expect_same_walks(test_scenes::cornell_box(), 9, 3000);
}

// Rays started on the triangles themselves, as bounce rays are.
TEST(TraversalNodeOrderTest, RaysFromSurfacesMatchOriginSideWalk) {
  const Scene scene = test_scenes::cornell_box();
  const BothWalks walks(scene, StreamSelection{.nodes = true, .lists = false, .triangles = true});
  std::mt19937 engine(21);
  int hits = 0;
  for (int i = 0; i < 4000 && !::testing::Test::HasFailure(); ++i) {
    const Triangle& t = scene.triangles[engine() % scene.triangles.size()];
    const float u = test_scenes::uniform(engine, 0, 1), v = test_scenes::uniform(engine, 0, 1 - u);
    const Vec3 origin = t.v0 + (t.v1 - t.v0) * u + (t.v2 - t.v0) * v;
    Vec3 direction{test_scenes::uniform(engine, -1, 1), test_scenes::uniform(engine, -1, 1),
                   test_scenes::uniform(engine, -1, 1)};
    if (i % 4 == 0) direction[static_cast<int>(engine() % 3)] = i % 8 ? 0.0f : -0.0f;
    if (walks.expect_same(Ray{origin, direction}, std::numeric_limits<float>::infinity(), false)) ++hits;
  }
  EXPECT_GT(hits, 0);
}

}  // namespace
}  // namespace nodetrace::tracer
