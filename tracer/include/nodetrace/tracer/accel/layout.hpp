// Tree layouts: where each kd-tree node lives in memory. A layout maps a node
// to a slot; the node's address is node_base + slot * node_size.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "nodetrace/tracer/accel/kdtree.hpp"

namespace nodetrace::tracer {

enum class LayoutKind : std::uint8_t {
  Dfl,     // depth-first (pre-order, left child next)
  Bfl,     // breadth-first (level order, left to right)
  Hybrid,  // levels < K in BFL, each subtree rooted at level K in DFL (the paper)
  Veb,     // van Emde Boas: top half of the levels, then each bottom subtree, recursively
};

std::string_view layout_name(LayoutKind kind);
std::optional<LayoutKind> parse_layout_name(std::string_view name);

struct Layout {
  LayoutKind kind = LayoutKind::Dfl;
  std::uint32_t split_level = 0;  // K of the hybrid layout (0 for the others)
  std::vector<std::uint32_t> slot_of_node;  // index = node index of KdTree::nodes()
};

// `split_level` is used by Hybrid only.
Layout make_layout(const KdTree& tree, LayoutKind kind, std::uint32_t split_level = 0);


}  // namespace nodetrace::tracer
