// What the kd-tree's builders make: each builder's nodes in pre-order, with
// the subtrees other builders made spliced in when the tree is assembled.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

#include "accel/block_list.hpp"
#include "nodetrace/tracer/accel/kdtree.hpp"

namespace nodetrace::tracer::kd_build {

struct BuiltNodes;

// A node as a builder makes it, half a KdNode: in a builder's pre-order a
// node's left child is always the next node, so an interior node keeps only
// its split and right child, a leaf its primitive range. The tree's
// KdNodes are made from these when it is assembled.
struct BuiltNode {
  std::uint32_t split_or_first = 0;  // interior: the split position's bits; leaf: its first primitive
  std::uint32_t right_or_count = 0;  // interior: its right child (or kSplicedRoot); leaf: its primitives
  std::uint16_t level = 0;           // root = 0
  std::uint8_t axis = KdNode::kLeafAxis;
  bool is_leaf() const { return axis == KdNode::kLeafAxis; }
};

// A subtree another builder made, to go between a builder's own nodes.
struct SplicedSubtree {
  std::uint32_t nodes_before = 0;       // the builder's own nodes before it
  std::uint32_t primitives_before = 0;  // and their primitives
  std::uint32_t parent = 0;             // the builder's node whose right child is its root
  std::unique_ptr<BuiltNodes> part;
};

// The right child of a node whose right subtree is spliced in.
constexpr std::uint32_t kSplicedRoot = std::numeric_limits<std::uint32_t>::max();

// Nodes one builder made, in pre-order: a whole tree, or a fragment of
// another builder's. Subtrees that other builders made are spliced in when
// the tree is assembled, so each node is copied once.
struct BuiltNodes {
  // Children and leaf ranges index these vectors alone.
  BlockList<BuiltNode> nodes;
  BlockList<std::uint32_t> primitives;
  // Each node's term of the tree's SAH cost, summed in pre-order at the end.
  BlockList<double> costs;
  std::vector<SplicedSubtree> spliced;  // in pre-order
  std::size_t spliced_nodes = 0, spliced_primitives = 0;  // in all of them, nested ones too
  std::size_t total_nodes() const { return nodes.size() + spliced_nodes; }
  std::size_t total_primitives() const { return primitives.size() + spliced_primitives; }
};

// Frees the costs of `part` and of the subtrees spliced into it: once the
// tree's SAH cost is summed they are not needed, and the tree's assembly
// is the build's high-water mark.
inline void release_costs(BuiltNodes& part) {
  part.costs = {};
  for (SplicedSubtree& subtree : part.spliced) release_costs(*subtree.part);
}

}  // namespace nodetrace::tracer::kd_build
