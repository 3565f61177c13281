// Layouts over every acceleration structure's tree: each a permutation of
// the nodes; the hybrid's levels < K the first slots; treelets contiguous,
// connected, within their byte budget and grown by surface area.
#include <gtest/gtest.h>

#include <algorithm>
#include <queue>

#include "nodetrace/tracer/accel/acceleration_structure.hpp"
#include "test_render_scenes.hpp"

namespace nodetrace::tracer {
namespace {

constexpr AccelKind kAllKinds[] = {AccelKind::KdTree, AccelKind::Bvh2, AccelKind::Bvh4, AccelKind::Bvh8,
                                   AccelKind::CwBvh8};
constexpr LayoutKind kAllLayouts[] = {LayoutKind::Dfl, LayoutKind::Bfl, LayoutKind::Hybrid, LayoutKind::Veb,
                                      LayoutKind::Treelet};

const std::vector<Triangle>& triangles() {
  static const auto t = test_scenes::random_triangles(4000, 17).triangles;
  return t;
}

std::vector<std::uint32_t> nodes_by_slot(const Layout& layout) {
  std::vector<std::uint32_t> order(layout.slot_of_node.size());
  for (std::uint32_t n = 0; n < order.size(); ++n) order[layout.slot_of_node[n]] = n;
  return order;
}

std::vector<std::uint32_t> parents(const TreeShape& shape) {
  std::vector<std::uint32_t> parent(shape.size(), 0xFFFFFFFFu);
  for (std::uint32_t n = 0; n < shape.size(); ++n) {
    for (auto c : shape.children_of(n)) parent[c] = n;
  }
  return parent;
}

TEST(AccelLayoutTest, EveryLayoutOfEveryTreeIsAPermutation) {
  for (const auto accel : kAllKinds) {
    const auto tree = AccelerationStructure::build(triangles(), accel);
    const TreeShape shape = tree.shape();
    ASSERT_EQ(shape.size(), tree.stats().nodes);
    for (const auto kind : kAllLayouts) {
      SCOPED_TRACE(std::string(accel_name(accel)) + " " + std::string(layout_name(kind)));
      const Layout layout = make_layout(shape, kind, 3, 4);
      std::vector<std::uint32_t> sorted = layout.slot_of_node;
      std::sort(sorted.begin(), sorted.end());
      ASSERT_EQ(sorted.size(), shape.size());
      for (std::uint32_t i = 0; i < sorted.size(); ++i) ASSERT_EQ(sorted[i], i) << "slot missing or used twice";
      EXPECT_EQ(layout.slot_of_node[0], 0u);
    }
  }
}

TEST(AccelLayoutTest, HybridTopLevelsAreTheFirstSlots) {
  for (const auto accel : kAllKinds) {
    SCOPED_TRACE(std::string(accel_name(accel)));
    const auto tree = AccelerationStructure::build(triangles(), accel);
    const TreeShape shape = tree.shape();
    for (std::uint32_t k : {1u, 2u, 3u}) {
      const Layout layout = make_layout(shape, LayoutKind::Hybrid, k);
      std::uint64_t top = 0;
      for (std::uint32_t l = 0; l < k && l < tree.stats().nodes_per_level.size(); ++l) {
        top += tree.stats().nodes_per_level[l];
      }
      for (std::uint32_t n = 0; n < shape.size(); ++n) {
        ASSERT_EQ(layout.slot_of_node[n] < top, shape.level[n] < k) << "node " << n << " K " << k;
      }
      // Below K each subtree is one contiguous block.
      const auto order = nodes_by_slot(layout);
      const auto parent = parents(shape);
      for (std::uint32_t s = top + 1; s < order.size(); ++s) {
        const std::uint32_t n = order[s];
        if (shape.level[n] == k) continue;  // a subtree root begins a block
        ASSERT_LT(layout.slot_of_node[parent[n]], s);
        ASSERT_GE(shape.level[parent[n]], k) << "a node below K follows its parent's block";
      }
    }
  }
}

TEST(AccelLayoutTest, TreeletsAreContiguousConnectedAndWithinBudget) {
  for (const auto accel : kAllKinds) {
    const auto tree = AccelerationStructure::build(triangles(), accel);
    const TreeShape shape = tree.shape();
    const auto parent = parents(shape);
    for (const std::uint32_t bytes : {64u, 256u, 4096u}) {
      SCOPED_TRACE(std::string(accel_name(accel)) + " " + std::to_string(bytes) + " B");
      const std::uint32_t per = treelet_nodes_for(bytes, default_node_size(accel));
      const Layout layout = make_layout(shape, LayoutKind::Treelet, 0, per);
      const auto order = nodes_by_slot(layout);
      auto starts = layout.treelet_first_slot;
      ASSERT_FALSE(starts.empty());
      ASSERT_EQ(starts.front(), 0u);
      ASSERT_TRUE(std::is_sorted(starts.begin(), starts.end()));
      starts.push_back(static_cast<std::uint32_t>(order.size()));
      for (std::size_t t = 0; t + 1 < starts.size(); ++t) {
        const std::uint32_t begin = starts[t], end = starts[t + 1];
        ASSERT_LT(begin, end);
        ASSERT_LE(end - begin, per);
        ASSERT_TRUE(end - begin == 1 || std::uint64_t(end - begin) * default_node_size(accel) <= bytes);
        // Connected: every member but the first has its parent earlier in
        // the same treelet; and a member joined as the largest-area child
        // of the members before it.
        for (std::uint32_t s = begin + 1; s < end; ++s) {
          const std::uint32_t p_slot = layout.slot_of_node[parent[order[s]]];
          ASSERT_TRUE(p_slot >= begin && p_slot < s) << "treelet " << t << " slot " << s;
          for (std::uint32_t m = begin; m < s; ++m) {
            for (auto c : shape.children_of(order[m])) {
              const std::uint32_t cs = layout.slot_of_node[c];
              if (cs >= s) {
                ASSERT_LE(shape.area[c], shape.area[order[s]]) << "a larger child was left out";
              }
            }
          }
        }
      }
    }
  }
}

TEST(AccelLayoutTest, KdTreeShapeGivesTheKdTreeLayouts) {
  const KdTree tree = KdTree::build(triangles());
  const TreeShape shape = kdtree_shape(tree);
  for (const auto kind : {LayoutKind::Dfl, LayoutKind::Bfl, LayoutKind::Hybrid, LayoutKind::Veb}) {
    EXPECT_EQ(make_layout(shape, kind, 4).slot_of_node, make_layout(tree, kind, 4).slot_of_node);
  }
  // DFL of the kd-tree is its pre-order: slot = node index.
  const Layout dfl = make_layout(shape, LayoutKind::Dfl);
  for (std::uint32_t n = 0; n < shape.size(); ++n) ASSERT_EQ(dfl.slot_of_node[n], n);
}

}  // namespace
}  // namespace nodetrace::tracer
