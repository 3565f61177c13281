#include "nodetrace/tracer/accel/bvh_traversal.hpp"

#include <cmath>
#include <stdexcept>

#include "accel/box_test.hpp"
#include "accel/leaf_visit.hpp"

namespace nodetrace::tracer {

using formats::Record;

BvhTraversal::BvhTraversal(const std::vector<Triangle>& triangles, const Bvh& bvh, const Layout& layout,
                           const StreamSelection& streams, const AddressMap& addresses)
    : triangles_(triangles), bvh_(bvh), streams_(streams), addresses_(addresses) {
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
}

template <bool AnyHit>
bool BvhTraversal::traverse(const Ray& ray, float t_max, Hit& hit, std::vector<Record>* records,
                            RenderStats* stats) const {
  const auto& nodes = bvh_.nodes();
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
  const detail::LeafVisit leaf{triangles_, bvh_.primitives(), sheared, streams_, addresses_, records};
  const auto& children = bvh_.children();
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
  while (true) {
    if (current.count == 0) {
      ++fetches;
      if (record_nodes) records->push_back(node_records_[current.index]);
      const BvhNode& node = nodes[current.index];
      // The children hit, nearest first (ties: stored order).
      Entry hits[8];
      int hit_count = 0;
      for (std::uint32_t k = 0; k < node.child_count; ++k) {
        const BvhChild& c = children[node.first_child + k];
        float t0 = 0, t1 = best;
        if (!detail::intersect_box_branchless(c.box, ray.origin, inverse, t0, t1)) continue;
        int j = hit_count++;
        for (; j > 0 && hits[j - 1].t > t0; --j) hits[j] = hits[j - 1];
        hits[j] = {t0, c.index, c.count};
      }
      if (hit_count > 0) {
        // The nearest is visited next; the others wait, farthest deepest.
        for (int j = hit_count - 1; j > 0; --j) stack[top++] = hits[j];
        current = hits[0];
        continue;
      }
    } else {
      ++leaves;
      if (leaf.visit<AnyHit>(current.index, current.count, best, hit, tests)) found = true;
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
  return traverse<false>(ray, t_max, hit, records, stats);
}

bool BvhTraversal::any_hit(const Ray& ray, float t_max, std::vector<Record>* records, RenderStats* stats) const {
  Hit hit;
  return traverse<true>(ray, t_max, hit, records, stats);
}

}  // namespace nodetrace::tracer
