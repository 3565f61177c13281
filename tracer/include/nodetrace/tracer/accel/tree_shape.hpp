// The shape of a stored tree, whatever its nodes hold: each node's level,
// its child nodes (nodes a traversal fetches, not leaf primitive ranges) and
// the surface area of its box. Layouts are computed over it, so one layout
// code serves the kd-tree and every BVH.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace nodetrace::tracer {

struct TreeShape {
  // Index 0 is the root; node i's children are
  // children[child_begin[i] .. child_begin[i + 1]) in their stored order
  // (a kd-tree: left, right; a BVH: the node's child slots).
  std::vector<std::uint16_t> level;
  std::vector<std::uint32_t> child_begin;  // size nodes + 1
  std::vector<std::uint32_t> children;
  std::vector<float> area;  // surface area of the node's box

  std::size_t size() const { return level.size(); }
  std::span<const std::uint32_t> children_of(std::uint32_t node) const {
    return {children.data() + child_begin[node], children.data() + child_begin[node + 1]};
  }
};

}  // namespace nodetrace::tracer
