// Layout invariants: every layout is a bijection onto 0..N-1; DFL is pre-order,
// BFL level order; hybrid's top is contiguous BFL and each lower subtree one
// contiguous DFL block; vEB on a complete tree gives the textbook order.
#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>

#include "nodetrace/base/split_level.hpp"
#include "nodetrace/tracer/accel/kdtree.hpp"
#include "nodetrace/tracer/accel/layout.hpp"
#include "test_render_scenes.hpp"

namespace nodetrace::tracer {
namespace {

const KdTree& sample_tree() {
  static const KdTree tree = KdTree::build(test_scenes::random_triangles(3000, 21).triangles);
  return tree;
}

void expect_bijection(const Layout& layout, std::size_t n) {
  ASSERT_EQ(layout.slot_of_node.size(), n);
  std::vector<std::uint32_t> sorted = layout.slot_of_node;
  std::sort(sorted.begin(), sorted.end());
  for (std::uint32_t i = 0; i < n; ++i) ASSERT_EQ(sorted[i], i) << "slot " << i << " missing or reused";
}

// Node indices listed by slot.
std::vector<std::uint32_t> nodes_by_slot(const Layout& layout) {
  std::vector<std::uint32_t> order(layout.slot_of_node.size());
  for (std::uint32_t n = 0; n < order.size(); ++n) order[layout.slot_of_node[n]] = n;
  return order;
}

// Size of the subtree at each node.
std::vector<std::uint32_t> subtree_sizes(const KdTree& tree) {
  const auto& nodes = tree.nodes();
  std::vector<std::uint32_t> size(nodes.size(), 1);
  for (std::size_t i = nodes.size(); i-- > 0;) {  // children follow parents in pre-order
    if (!nodes[i].is_leaf()) size[i] = 1 + size[nodes[i].left] + size[nodes[i].right];
  }
  return size;
}

TEST(LayoutTest, EveryLayoutIsABijection) {
  const KdTree& tree = sample_tree();
  for (auto kind : {LayoutKind::Dfl, LayoutKind::Bfl, LayoutKind::Hybrid, LayoutKind::Veb}) {
    SCOPED_TRACE(std::string(layout_name(kind)));
    const Layout layout = make_layout(tree, kind, 6);
    expect_bijection(layout, tree.nodes().size());
    EXPECT_EQ(layout.slot_of_node[0], 0u);  // the root comes first in all of them
  }
}

TEST(LayoutTest, DflIsPreOrderAndBflIsLevelOrder) {
  const KdTree& tree = sample_tree();
  const Layout dfl = make_layout(tree, LayoutKind::Dfl);
  for (std::uint32_t n = 0; n < tree.nodes().size(); ++n) EXPECT_EQ(dfl.slot_of_node[n], n);
  const Layout bfl = make_layout(tree, LayoutKind::Bfl);
  const auto order = nodes_by_slot(bfl);
  for (std::size_t s = 1; s < order.size(); ++s) {
    ASSERT_LE(tree.nodes()[order[s - 1]].level, tree.nodes()[order[s]].level);
  }
  // Children of consecutive parents are consecutive, left before right.
  for (const auto& node : tree.nodes()) {
    if (!node.is_leaf()) {
      EXPECT_EQ(bfl.slot_of_node[node.right], bfl.slot_of_node[node.left] + 1);
    }
  }
}

TEST(LayoutTest, HybridTopIsBflAndEachLowerSubtreeIsAContiguousDflBlock) {
  const KdTree& tree = sample_tree();
  const auto& nodes = tree.nodes();
  for (std::uint32_t k : {0u, 1u, 4u, 7u, 100u}) {
    SCOPED_TRACE("K = " + std::to_string(k));
    const Layout hybrid = make_layout(tree, LayoutKind::Hybrid, k);
    EXPECT_EQ(hybrid.split_level, k);
    expect_bijection(hybrid, nodes.size());
    const Layout bfl = make_layout(tree, LayoutKind::Bfl);
    std::uint64_t top = 0;
    for (std::size_t l = 0; l < std::min<std::size_t>(k, tree.stats().nodes_per_level.size()); ++l) {
      top += tree.stats().nodes_per_level[l];
    }
    // Top: the first `top` slots, in the BFL order (same slots as BFL).
    for (std::uint32_t n = 0; n < nodes.size(); ++n) {
      if (nodes[n].level < k) {
        EXPECT_EQ(hybrid.slot_of_node[n], bfl.slot_of_node[n]);
      } else {
        EXPECT_GE(hybrid.slot_of_node[n], top);
      }
    }
    // Below: each subtree rooted at level K occupies [slot(root), slot(root) +
    // size) with its nodes in pre-order; roots follow each other in BFL order.
    const auto sizes = subtree_sizes(tree);
    std::vector<std::uint32_t> roots;
    for (std::uint32_t n = 0; n < nodes.size(); ++n) {
      if (nodes[n].level == k) roots.push_back(n);
    }
    std::sort(roots.begin(), roots.end(), [&](auto a, auto b) { return bfl.slot_of_node[a] < bfl.slot_of_node[b]; });
    std::uint64_t expected_start = top;
    for (auto root : roots) {
      EXPECT_EQ(hybrid.slot_of_node[root], expected_start);
      // Pre-order indices of the subtree are root..root+size-1 (DFL build order).
      for (std::uint32_t i = 0; i < sizes[root]; ++i) {
        ASSERT_EQ(hybrid.slot_of_node[root + i], expected_start + i);
      }
      expected_start += sizes[root];
    }
    EXPECT_EQ(expected_start, nodes.size());
  }
}

// A complete tree of 4 levels (15 nodes) in pre-order.
KdTree complete_tree() {
  std::vector<KdNode> nodes;
  auto add = [&](auto&& self, int level) -> std::uint32_t {
    const auto index = static_cast<std::uint32_t>(nodes.size());
    nodes.emplace_back();
    nodes[index].level = static_cast<std::uint16_t>(level);
    if (level < 3) {
      nodes[index].axis = 0;
      const auto left = self(self, level + 1);
      const auto right = self(self, level + 1);
      nodes[index].left = left;
      nodes[index].right = right;
    }
    return index;
  };
  add(add, 0);
  Bounds box;
  box.lo = {0, 0, 0};
  box.hi = {1, 1, 1};
  return KdTree::from_nodes(std::move(nodes), {}, box);
}

TEST(LayoutTest, VanEmdeBoasOnACompleteTree) {
  const KdTree tree = complete_tree();
  ASSERT_EQ(tree.nodes().size(), 15u);
  const Layout veb = make_layout(tree, LayoutKind::Veb);
  expect_bijection(veb, 15);
  // Pre-order indices: root 0; level 1: 1, 8; level 2: 2, 5, 9, 12; leaves
  // 3, 4, 6, 7, 10, 11, 13, 14. vEB: top tree (root, 1, 8), then the four
  // bottom trees (2,3,4) (5,6,7) (9,10,11) (12,13,14).
  const std::vector<std::uint32_t> expected{0, 1, 8, 2, 3, 4, 5, 6, 7, 9, 10, 11, 12, 13, 14};
  EXPECT_EQ(nodes_by_slot(veb), expected);
}

TEST(LayoutTest, SplitLevelForHighSize) {
  const std::vector<std::uint64_t> per_level{1, 2, 4, 8};
  EXPECT_EQ(base::split_level_for_capacity(per_level, base::LevelPlacement::contiguous_bytes(8), 4096), 4u);
  EXPECT_EQ(base::split_level_for_capacity(per_level, base::LevelPlacement::contiguous_bytes(8), 24), 2u);
  EXPECT_EQ(base::split_level_for_capacity(per_level, base::LevelPlacement::contiguous_bytes(8), 23), 1u);
  EXPECT_EQ(base::split_level_for_capacity(per_level, base::LevelPlacement::contiguous_bytes(8), 56), 3u);
  EXPECT_EQ(base::split_level_for_capacity(per_level, base::LevelPlacement::contiguous_bytes(8), 7), 0u);
}

TEST(LayoutTest, NamesRoundTrip) {
  for (auto kind : {LayoutKind::Dfl, LayoutKind::Bfl, LayoutKind::Hybrid, LayoutKind::Veb, LayoutKind::Treelet}) {
    EXPECT_EQ(parse_layout_name(layout_name(kind)), kind);
  }
  EXPECT_FALSE(parse_layout_name("zigzag").has_value());
}

}  // namespace
}  // namespace nodetrace::tracer
