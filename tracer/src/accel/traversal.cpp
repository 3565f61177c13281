#include "nodetrace/tracer/accel/traversal.hpp"

#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

#include "accel/box_test.hpp"
#include "nodetrace/base/huge_pages.hpp"
#include "accel/leaf_visit.hpp"

namespace nodetrace::tracer {

using formats::Record;

using detail::intersect_box;

Traversal::Traversal(const std::vector<Triangle>& triangles, const KdTree& tree, const Layout& layout,
                     const StreamSelection& streams, const AddressMap& addresses)
    : listed_triangles_(detail::triangles_in_list_order(triangles, tree.primitives())),
      tree_(tree),
      streams_(streams),
      addresses_(addresses) {
  const auto& slots = layout.slot_of_node;
  const auto& nodes = tree.nodes();
  if (slots.size() != nodes.size()) throw std::invalid_argument("layout does not match the kd-tree");
  base::reserve_on_huge_pages(node_records_, nodes.size());
  base::reserve_on_huge_pages(compact_, nodes.size());
  node_records_.resize(nodes.size());
  compact_.resize(nodes.size());
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    const KdNode& n = nodes[i];
    node_records_[i] = {.address = addresses.node_base + std::uint64_t{slots[i]} * addresses.node_size,
                        .size = addresses.node_size,
                        .type = formats::AccessType::Read,
                        .tag = static_cast<formats::Tag>(n.level)};
    if (n.is_leaf()) {
      compact_[i].first = n.first;
      compact_[i].bits = (n.count << 2) | KdNode::kLeafAxis;
    } else {
      // Traversal finds the left child next to its parent (pre-order).
      if (n.left != i + 1) throw std::invalid_argument("kd-tree nodes are not in pre-order");
      compact_[i].split = n.split;
      compact_[i].bits = (n.right << 2) | n.axis;
    }
  }
}

template <bool AnyHit, bool Recording, unsigned Octant>
bool Traversal::traverse(const Ray& ray, float t_max, Hit& hit, std::vector<Record>* records,
                         RenderStats* stats) const {
  if (compact_.empty() || tree_.bounds().empty()) return false;
  // A ray with a non-finite or zero part meets nothing: without this its
  // NaN comparisons would send it to every node of the tree.
  const auto finite = [](const Vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); };
  if (!finite(ray.origin) || !finite(ray.direction) || ray.direction == Vec3{}) return false;
  const Vec3 inverse{1.0f / ray.direction.x, 1.0f / ray.direction.y, 1.0f / ray.direction.z};
  float t_min = 0, t_far = t_max;
  if (!intersect_box(tree_.bounds(), ray.origin, inverse, t_min, t_far)) return false;

  if constexpr (!Recording) records = nullptr;
  const detail::ShearedRay sheared(ray);
  const detail::LeafVisit leaf{listed_triangles_, tree_.primitives(), sheared, streams_, addresses_, records};
  const bool record_nodes = Recording && streams_.nodes;
  struct Pending {
    std::uint32_t node;
    float t_min, t_max;
  };
  Pending stack[kMaxLevelLimit + 2];
  Pending* top = stack;  // the next free entry
  // Locals the compiler can keep in registers: the record vector's writes
  // could otherwise alias the members.
  const CompactNode* const nodes = compact_.data();
  const formats::Record* const node_records = node_records_.data();
  const float origin[3] = {ray.origin.x, ray.origin.y, ray.origin.z};
  const float inverse_direction[3] = {inverse.x, inverse.y, inverse.z};
  const bool direction_not_positive[3] = {ray.direction.x <= 0, ray.direction.y <= 0, ray.direction.z <= 0};
  // Bit a set when the direction's sign bit on axis a is: a ray crossing a
  // split on that axis meets the right (upper) child first. A template
  // constant: the near child no longer waits on an origin-vs-split compare,
  // and where it depends on the node's axis GCC branches on the bit, well
  // predicted, so the next node's load is issued speculatively (a mask
  // select instead, no branch, measured 15-20% slower on primary and shadow
  // rays: the load waits on the select).
  constexpr std::uint32_t right_first = Octant;
  std::uint32_t node_index = 0;
  float best = t_max;
  bool found = false;
  std::uint64_t fetches = 0, leaves = 0, tests = 0;
  detail::TestedTriangles tested;

  while (true) {
    const CompactNode node = nodes[node_index];
    ++fetches;
    if (record_nodes) records->push_back(node_records[node_index]);
    const std::uint32_t axis = node.bits & 3u;
    if (node.bits == KdNode::kLeafAxis) {
      // A leaf without triangles (most leaves a ray meets): one branch,
      // not a leaf branch and then a count branch.
      ++leaves;
    } else if (axis != KdNode::kLeafAxis) {
      const float o = origin[axis];
      const float t_split = (node.split - o) * inverse_direction[axis];
      const std::uint32_t left = node_index + 1, right = node.bits >> 2;
      // The right child's line is asked for as soon as its index is known:
      // the left child is next in memory, the right one is far away and,
      // when the step takes it (far-only, or a mispredicted near-only step)
      // or pops it later, its load would otherwise start only once the
      // compares below are resolved. Kitchen's bounce rays gain 2-7 % (in
      // one process, paired rounds); Robot's coherent primary rays lose
      // about 5 % across processes (the line is mostly cached).
      __builtin_prefetch(&nodes[right]);
      const bool right_near = (right_first >> axis) & 1u;
      const std::uint32_t near = right_near ? right : left;
      const std::uint32_t far = right_near ? left : right;
      // The steps are those of the origin-side rule (the ray's first child is
      // the one holding its origin, the origin on the plane going with the
      // direction): a nonzero t_split has the sign of (split - origin) times
      // the direction's sign, so t_split > 0 puts the origin on the near
      // side and t_split < 0 on the far side (the ray leaves the plane
      // behind). Only 0 and NaN (origin on the plane, or a zero or tiny
      // direction component) need the origin compare.
      // The cases are tested commonest first (Kitchen's path-traced rays:
      // near only 35%, far only 42%, both 22% of interior steps), one or two
      // compares where there were two or three. The same steps: t_min and
      // t_far are >= 0 (-0 included) or NaN, so t_split > t_far implies
      // t_split > 0, and a negative t_split is caught by t_split < t_min
      // unless t_min is NaN, when the t_split < 0 test below takes it. A
      // t_split of 0 with t_min > 0 now takes the far child, which holds
      // the segment, where the origin compare took the origin's side; the
      // two agree when the origin is on the plane (the far child is the
      // side the direction leaves to), and t_split is 0 only then unless
      // (split - origin) / direction underflows: |split - origin| below
      // 1.4e-45 times the direction component (bounce rays are unit
      // vectors; a shadow ray's direction is scene-sized, so a split and
      // an origin both within about 1e-40 of 0, and unequal).
      if (t_split > t_far) {
        node_index = near;
      } else if (t_split < t_min) {
        node_index = far;
      } else if (t_split > 0) {
        *top++ = {far, t_split, t_far};
        node_index = near;
        t_far = t_split;
      } else if (t_split < 0) {
        node_index = far;
      } else [[unlikely]] {
        const bool below_first = o < node.split || (o == node.split && direction_not_positive[axis]);
        const std::uint32_t first = below_first ? left : right;
        const std::uint32_t second = below_first ? right : left;
        if (t_split <= 0) {  // 0: the origin's side; NaN goes on
          node_index = first;
        } else {
          // NaN: no compare holds, both children are walked and t_far
          // becomes NaN, as the origin-side rule has always done.
          *top++ = {second, t_split, t_far};
          node_index = first;
          t_far = t_split;
        }
      }
      continue;
    } else {
      ++leaves;
      if (leaf.visit<AnyHit>(node.first, node.bits >> 2, best, hit, tests, tested)) found = true;
    }
    if constexpr (AnyHit) {
      if (found) break;
    }
    // The closest hit so far is final once it lies within this leaf's span;
    // a hit found past the span is kept (clipping rounding), not discarded.
    if (found && best <= t_far) break;
    if (top == stack) break;
    // Read field by field: a copy of the whole entry went through a stack
    // temporary, a store and a reload before the next node's load.
    const Pending& next = *--top;
    if (found && best < next.t_min) break;
    node_index = next.node;
    t_min = next.t_min;
    t_far = next.t_max;
  }
  if (stats) {
    stats->node_fetches += fetches;
    stats->leaf_visits += leaves;
    stats->triangle_tests += tests;
  }
  return found;
}

template <bool AnyHit, bool Recording>
bool Traversal::walk(const Ray& ray, float t_max, Hit& hit, std::vector<Record>* records, RenderStats* stats) const {
  static constexpr auto kWalks = []<unsigned... Octants>(std::integer_sequence<unsigned, Octants...>) {
    return std::array{&Traversal::traverse<AnyHit, Recording, Octants>...};
  }(std::make_integer_sequence<unsigned, 8>{});
  const Vec3& d = ray.direction;
  const unsigned octant = (std::signbit(d.x) ? 1u : 0u) | (std::signbit(d.y) ? 2u : 0u) | (std::signbit(d.z) ? 4u : 0u);
  return (this->*kWalks[octant])(ray, t_max, hit, records, stats);
}

bool Traversal::closest_hit(const Ray& ray, float t_max, Hit& hit, std::vector<Record>* records,
                            RenderStats* stats) const {
  return records ? walk<false, true>(ray, t_max, hit, records, stats)
                 : walk<false, false>(ray, t_max, hit, nullptr, stats);
}

bool Traversal::any_hit(const Ray& ray, float t_max, std::vector<Record>* records, RenderStats* stats) const {
  Hit hit;
  return records ? walk<true, true>(ray, t_max, hit, records, stats)
                 : walk<true, false>(ray, t_max, hit, nullptr, stats);
}

}  // namespace nodetrace::tracer
