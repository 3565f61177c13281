#include "nodetrace/tracer/accel/bvh_traversal.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

#include "accel/box_test.hpp"
#include "nodetrace/base/huge_pages.hpp"
#include "accel/leaf_visit.hpp"

namespace nodetrace::tracer {

using formats::Record;

BvhTraversal::BvhTraversal(const std::vector<Triangle>& triangles, const Bvh& bvh, const Layout& layout,
                           const StreamSelection& streams, const AddressMap& addresses)
    : listed_triangles_(detail::triangles_in_list_order(triangles, bvh.primitives())),
      bvh_(bvh),
      streams_(streams),
      addresses_(addresses) {
  const auto& slots = layout.slot_of_node;
  const auto& nodes = bvh.nodes();
  if (slots.size() != nodes.size()) throw std::invalid_argument("layout does not match the BVH");
  node_records_.resize(nodes.size());
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    node_records_[i] = {.address = addresses.node_base + std::uint64_t{slots[i]} * addresses.node_size,
                        .size = addresses.node_size,
                        .type = formats::AccessType::Read,
                        .tag = static_cast<formats::Tag>(nodes[i].level)};
  }
  switch (bvh.arity()) {
    case 2: fill(nodes2_); break;
    case 4: fill(nodes4_); break;
    default: fill(nodes8_); break;
  }
}

template <unsigned W>
void BvhTraversal::fill(std::vector<WideNode<W>>& wide) const {
  const auto& nodes = bvh_.nodes();
  base::reserve_on_huge_pages(wide, nodes.size());
  wide.assign(nodes.size(), WideNode<W>{});
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    if (nodes[i].child_count > W) throw std::invalid_argument("BVH node wider than its tree's arity");
    wide[i].child_count = nodes[i].child_count;
    for (std::uint32_t k = 0; k < nodes[i].child_count; ++k) {
      const BvhChild& c = bvh_.children()[nodes[i].first_child + k];
      for (int axis = 0; axis < 3; ++axis) {
        wide[i].lo[axis][k] = c.box.lo[axis];
        wide[i].hi[axis][k] = c.box.hi[axis];
      }
      wide[i].index[k] = c.index;
      wide[i].count[k] = c.count;
    }
  }
}

template <bool AnyHit>
bool BvhTraversal::dispatch(const Ray& ray, float t_max, Hit& hit, std::vector<Record>* records,
                            RenderStats* stats) const {
  if (!nodes2_.empty()) return traverse<AnyHit>(nodes2_, ray, t_max, hit, records, stats);
  if (!nodes4_.empty()) return traverse<AnyHit>(nodes4_, ray, t_max, hit, records, stats);
  return traverse<AnyHit>(nodes8_, ray, t_max, hit, records, stats);
}

template <bool AnyHit, unsigned W>
bool BvhTraversal::traverse(const std::vector<WideNode<W>>& nodes, const Ray& ray, float t_max, Hit& hit,
                            std::vector<Record>* records, RenderStats* stats) const {
  if (nodes.empty()) return false;
  // A ray with a non-finite or zero part meets nothing (as the kd-tree's).
  const auto finite = [](const Vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); };
  if (!finite(ray.origin) || !finite(ray.direction) || ray.direction == Vec3{}) return false;
  const Vec3 inverse{1.0f / ray.direction.x, 1.0f / ray.direction.y, 1.0f / ray.direction.z};
  {
    float t0 = 0, t1 = t_max;
    if (!detail::intersect_box(bvh_.bounds(), ray.origin, inverse, t0, t1)) return false;
  }
  const detail::ShearedRay sheared(ray);
  const detail::LeafVisit leaf{listed_triangles_, bvh_.primitives(), sheared, streams_, addresses_, records};
  const bool record_nodes = records && streams_.nodes;

  // A node visit pushes at most arity - 1 entries (its nearest child is
  // visited next without the stack), and no tree is deeper than kBvhMaxLevels.
  struct Entry {
    float t;
    std::uint32_t index, count;  // count 0: a node
  };
  Entry stack[kBvhMaxLevels * 7 + 8];
  int top = 0;
  Entry current{0.0f, 0, 0};  // the root
  float best = t_max;
  bool found = false;
  std::uint64_t fetches = 0, leaves = 0, tests = 0;
  detail::NoTestedTriangles no_tested;
  while (true) {
    if (current.count == 0) {
      ++fetches;
      if (record_nodes) records->push_back(node_records_[current.index]);
      const WideNode<W>& node = nodes[current.index];
      // Every child box at once: detail::intersect_box's slab test (its
      // conservative rounding, NaN bounds ignored) without its early exits,
      // plane by plane; then the children hit, nearest first (ties: stored order).
      constexpr float kGrow = 1.0f + 2.0f * 3.0f * std::numeric_limits<float>::epsilon();
      float t_near[W], t_far[W];
      for (unsigned k = 0; k < W; ++k) {
        t_near[k] = 0.0f;
        t_far[k] = best;
      }
      for (int axis = 0; axis < 3; ++axis) {
        const float o = ray.origin[axis], inv = inverse[axis];
        for (unsigned k = 0; k < W; ++k) {
          const float a = (node.lo[axis][k] - o) * inv;
          const float b = (node.hi[axis][k] - o) * inv;
          const float near = a > b ? b : a;
          const float far = (a > b ? a : b) * kGrow;
          t_near[k] = near > t_near[k] ? near : t_near[k];
          t_far[k] = far < t_far[k] ? far : t_far[k];
        }
      }
      Entry hits[W];
      int hit_count = 0;
      for (std::uint32_t k = 0; k < node.child_count; ++k) {
        if (!(t_near[k] <= t_far[k])) continue;
        const float t0 = t_near[k];
        int j = hit_count++;
        for (; j > 0 && hits[j - 1].t > t0; --j) hits[j] = hits[j - 1];
        hits[j] = {t0, node.index[k], node.count[k]};
      }
      if (hit_count > 0) {
        // The nearest is visited next; the others wait, farthest deepest.
        for (int j = hit_count - 1; j > 0; --j) stack[top++] = hits[j];
        current = hits[0];
        continue;
      }
    } else {
      ++leaves;
      if (leaf.visit<AnyHit>(current.index, current.count, best, hit, tests, no_tested)) found = true;
      if constexpr (AnyHit) {
        if (found) break;
      }
    }
    // The next entry still nearer than the closest hit; the others are
    // never read.
    while (top > 0 && stack[top - 1].t > best) --top;
    if (top == 0) break;
    current = stack[--top];
  }
  if (stats) {
    stats->node_fetches += fetches;
    stats->leaf_visits += leaves;
    stats->triangle_tests += tests;
  }
  return found;
}

bool BvhTraversal::closest_hit(const Ray& ray, float t_max, Hit& hit, std::vector<Record>* records,
                               RenderStats* stats) const {
  return dispatch<false>(ray, t_max, hit, records, stats);
}

bool BvhTraversal::any_hit(const Ray& ray, float t_max, std::vector<Record>* records, RenderStats* stats) const {
  Hit hit;
  return dispatch<true>(ray, t_max, hit, records, stats);
}

}  // namespace nodetrace::tracer
