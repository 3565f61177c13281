// The kd-tree's leaf-size rule (--leaf-size): a node of at most N triangles
// is a leaf; the tree is otherwise the one the SAH builds, cut there.
#include <gtest/gtest.h>

#include <set>
#include <tuple>
#include <vector>

#include "nodetrace/tracer/accel/kdtree.hpp"
#include "test_render_scenes.hpp"

namespace nodetrace::tracer {
namespace {

// The triangles under a node: those of the leaves below it.
std::set<std::uint32_t> triangles_below(const KdTree& tree, std::uint32_t index) {
  const KdNode& node = tree.nodes()[index];
  if (node.is_leaf()) {
    return {tree.primitives().begin() + node.first, tree.primitives().begin() + node.first + node.count};
  }
  auto left = triangles_below(tree, node.left);
  const auto right = triangles_below(tree, node.right);
  left.insert(right.begin(), right.end());
  return left;
}

// The default tree cut at every node of at most `leaf_size` triangles, in
// pre-order: (level, axis, split or leaf size) per node.
void pruned(const KdTree& tree, std::uint32_t index, std::uint32_t leaf_size,
            std::vector<std::tuple<int, int, float>>& out) {
  const KdNode& node = tree.nodes()[index];
  const auto count = triangles_below(tree, index).size();
  if (node.is_leaf() || count <= leaf_size) {
    out.emplace_back(node.level, KdNode::kLeafAxis, float(count));
    return;
  }
  out.emplace_back(node.level, node.axis, node.split);
  pruned(tree, node.left, leaf_size, out);
  pruned(tree, node.right, leaf_size, out);
}

TEST(KdLeafSizeTest, SplitsOnlyNodesOfMoreTrianglesAndIsTheDefaultTreeCutThere) {
  const Scene scene = test_scenes::random_triangles(3000, 7);
  const KdTree plain = KdTree::build(scene.triangles);
  KdBuildOptions zero;
  zero.leaf_size = 0;
  EXPECT_EQ(KdTree::build(scene.triangles, zero).nodes().size(), plain.nodes().size());
  for (const std::uint32_t leaf_size : {2u, 4u, 8u}) {
    KdBuildOptions options;
    options.leaf_size = leaf_size;
    const KdTree tree = KdTree::build(scene.triangles, options);
    EXPECT_LT(tree.nodes().size(), plain.nodes().size()) << leaf_size;
    for (std::uint32_t i = 0; i < tree.nodes().size(); ++i) {
      if (!tree.nodes()[i].is_leaf()) {
        EXPECT_GT(triangles_below(tree, i).size(), leaf_size) << "node " << i;
      }
    }
    std::vector<std::tuple<int, int, float>> expected, got;
    pruned(plain, 0, leaf_size, expected);
    for (std::uint32_t i = 0; i < tree.nodes().size(); ++i) {
      const KdNode& node = tree.nodes()[i];
      got.emplace_back(node.level, node.axis, node.is_leaf() ? float(triangles_below(tree, i).size()) : node.split);
    }
    EXPECT_TRUE(got == expected) << "leaf size " << leaf_size;
  }
}

}  // namespace
}  // namespace nodetrace::tracer
