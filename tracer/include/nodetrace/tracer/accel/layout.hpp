// Tree layouts: where each node of a tree (kd-tree or BVH) lives in memory.
// A layout maps a node to a slot; the node's address is
// node_base + slot * node_size.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "nodetrace/tracer/accel/kdtree.hpp"
#include "nodetrace/tracer/accel/tree_shape.hpp"

namespace nodetrace::tracer {

enum class LayoutKind : std::uint8_t {
  Dfl,     // depth-first (pre-order, first child next)
  Bfl,     // breadth-first (level order, children in their stored order)
  Hybrid,  // levels < K in BFL, each subtree rooted at level K in DFL (the paper)
  Veb,     // van Emde Boas: top half of the levels, then each bottom subtree, recursively
  Treelet, // groups of at most a byte budget grown greedily by surface area, each contiguous
};

std::string_view layout_name(LayoutKind kind);
std::optional<LayoutKind> parse_layout_name(std::string_view name);

// Treelets of 64 bytes unless told otherwise: one cache block of the
// largest block size the experiments simulate.
inline constexpr std::uint32_t kDefaultTreeletBytes = 64;

struct Layout {
  LayoutKind kind = LayoutKind::Dfl;
  std::uint32_t split_level = 0;  // K of the hybrid layout (0 for the others)
  std::vector<std::uint32_t> slot_of_node;  // index = node index of the tree
  // Treelet only: the first slot of each treelet, increasing.
  std::vector<std::uint32_t> treelet_first_slot;
};

// `split_level` is used by Hybrid only; `treelet_nodes` (nodes per treelet,
// at least 1) by Treelet only.
Layout make_layout(const TreeShape& shape, LayoutKind kind, std::uint32_t split_level = 0,
                   std::uint32_t treelet_nodes = 1);
Layout make_layout(const KdTree& tree, LayoutKind kind, std::uint32_t split_level = 0,
                   std::uint32_t treelet_nodes = 1);

// Nodes per treelet for a byte budget: as many whole nodes as fit, at least one.
std::uint32_t treelet_nodes_for(std::uint32_t treelet_bytes, std::uint32_t node_size);

// The kd-tree's shape: children left then right, areas of the boxes its
// splits cut from the root box.
TreeShape kdtree_shape(const KdTree& tree);

}  // namespace nodetrace::tracer
