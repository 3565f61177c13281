// Bounding volume hierarchies as ray-tracing hardware stores them: a binary
// BVH built with binned SAH, and wide BVHs (4 or 8 children) collapsed from
// it, optionally with compressed nodes whose child boxes are quantized.
//
// A node holds its children's boxes and references (Aila and Laine 2009):
// a child is another node, or a leaf, which is a range of triangles read
// straight from the node, so leaves are not nodes and are never fetched as
// one. A traversal fetches a node once per visit and tests all its
// children's boxes.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "nodetrace/tracer/accel/kdtree.hpp"
#include "nodetrace/tracer/accel/tree_shape.hpp"
#include "nodetrace/tracer/scene/scene.hpp"

namespace nodetrace::tracer {

struct BvhBuildOptions {
  float traversal_cost = 1.0f;     // SAH cost of visiting a node (fetch and box tests)
  float intersection_cost = 1.0f;  // SAH cost of one ray/triangle test
  // A node of more triangles than this is always split; at most this many
  // become a leaf when the SAH says a leaf is cheaper.
  std::uint32_t max_leaf_size = 4;
  std::uint32_t bins = 16;  // SAH candidate planes per axis: bins - 1
};

// A binary node deeper than this is split at the median along its widest
// axis whatever the SAH says, so no tree is deeper than kBvhMaxBinaryLevel +
// 32 levels and a fixed traversal stack always suffices.
inline constexpr std::uint32_t kBvhMedianFromLevel = 40;
inline constexpr std::uint32_t kBvhMaxLevels = kBvhMedianFromLevel + 33;

struct BvhChild {
  Bounds box;                // what traversal tests (compressed nodes: the dequantized box)
  std::uint32_t index = 0;   // a node: its index; a leaf: its first primitive
  std::uint32_t count = 0;   // 0: a node; else a leaf of this many primitives
  bool is_leaf() const { return count != 0; }
};

struct BvhNode {
  std::uint32_t first_child = 0;  // into Bvh::children()
  std::uint16_t child_count = 0;
  std::uint16_t level = 0;        // root 0, in the tree as stored (wide levels for wide trees)
};

// A compressed node's quantization (Ylitie, Karras and Laine 2017): child
// boxes on a grid of 2^exponent steps from the origin, 8 bits per plane,
// the minimum rounded down and the maximum up so the dequantized box
// contains the exact one.
struct BvhQuantization {
  Vec3 origin;
  std::array<std::int16_t, 3> exponent{};
};

class Bvh {
 public:
  // Deterministic: the same triangles and options give the same tree,
  // whatever the thread count. `arity` 2, 4 or 8; `compressed` quantizes
  // child boxes (arity 8 only in the node formats named).
  static Bvh build(std::span<const Triangle> triangles, unsigned arity, bool compressed,
                   const BvhBuildOptions& options = {});

  unsigned arity() const { return arity_; }
  bool compressed() const { return compressed_; }
  // Nodes in pre-order (index 0 is the root); each node's children are
  // children()[first_child, first_child + child_count), in space order.
  const std::vector<BvhNode>& nodes() const { return nodes_; }
  const std::vector<BvhChild>& children() const { return children_; }
  // Compressed trees: the exact child boxes, parallel to children(), and each
  // node's quantization; empty otherwise.
  const std::vector<Bounds>& exact_child_boxes() const { return exact_boxes_; }
  const std::vector<BvhQuantization>& quantizations() const { return quantizations_; }
  const std::vector<std::uint32_t>& primitives() const { return primitives_; }
  const Bounds& bounds() const { return bounds_; }
  // nodes: fetchable nodes; interior = nodes; leaves: leaf children;
  // empty_leaves 0; primitive_references: sum of leaf sizes.
  const KdTreeStats& stats() const { return stats_; }
  TreeShape shape() const;

 private:
  unsigned arity_ = 2;
  bool compressed_ = false;
  std::vector<BvhNode> nodes_;
  std::vector<BvhChild> children_;
  std::vector<Bounds> exact_boxes_;
  std::vector<BvhQuantization> quantizations_;
  std::vector<std::uint32_t> primitives_;
  Bounds bounds_;
  KdTreeStats stats_;
  friend class BvhBuilder;
  friend struct TreeCacheCodec;  // stores and restores every member (tree_cache_file)
};

}  // namespace nodetrace::tracer
