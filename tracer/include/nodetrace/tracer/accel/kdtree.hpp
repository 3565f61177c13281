// SAH kd-tree over a scene's triangles: O(N log N) event-sorting build
// (Wald and Havran 2006, "On building fast kd-trees for ray tracing, and on
// doing that in O(N log N)"), with perfect splits (triangles clipped to the
// node box) and an empty-space bonus. Events are kept per axis and radix
// sorted. Threads share the work by stealing: where both children of a split
// hold 512 triangles or more, an idle thread may take the right one while
// the left is built; subtrees built apart are spliced in pre-order, so the
// tree is the same for any number of threads.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "nodetrace/tracer/scene/scene.hpp"

namespace nodetrace::tracer {

struct KdBuildOptions {
  float traversal_cost = 1.0f;     // K_T: cost of one traversal step
  float intersection_cost = 1.5f;  // K_I: cost of one ray/triangle test
  float empty_bonus = 0.2f;        // cost reduction for cutting off empty space (0..1)
  int max_depth = 0;               // deepest level of a node; 0: 8 + 1.3 log2 N
  // A node of at most this many triangles is a leaf whatever the SAH says
  // (the minimum to split is one more); 0: the SAH alone decides.
  std::uint32_t leaf_size = 0;
  // Threads building the tree (0: one per core). The tree does not depend on it.
  unsigned threads = 0;
};

// The depth limit used when KdBuildOptions::max_depth is 0.
int default_max_depth(std::size_t triangle_count);
// No node is deeper than this, whatever the options say.
inline constexpr int kMaxLevelLimit = 100;

// One node. Interior nodes split `axis` at `split`; leaves (axis == kLeafAxis)
// hold primitives()[first, first + count).
struct KdNode {
  static constexpr std::uint8_t kLeafAxis = 3;
  float split = 0;
  std::uint32_t left = 0, right = 0;   // child node indices (interior)
  std::uint32_t first = 0, count = 0;  // primitive range (leaf)
  std::uint16_t level = 0;             // root = 0
  std::uint8_t axis = kLeafAxis;
  bool is_leaf() const { return axis == kLeafAxis; }
};

struct KdTreeStats {
  std::uint64_t nodes = 0, interior = 0, leaves = 0, empty_leaves = 0;
  std::uint64_t primitive_references = 0;     // sum of leaf sizes
  std::vector<std::uint64_t> nodes_per_level;  // index = level
  std::uint32_t depth = 0;                     // deepest level (root-only tree: 0)
  int depth_limit = 0;
  double mean_leaf_size = 0;           // over all leaves
  double mean_nonempty_leaf_size = 0;  // over leaves holding a triangle
  double sah_cost = 0;                 // expected cost of a ray through the root box
  double build_seconds = 0;            // wall time; never written into traces
  double build_cpu_seconds = 0;        // the process's CPU time (every thread) during the build
  bool loaded = false;                 // read from the tree cache: the build times are the loading's
};

class KdTree {
 public:
  // Deterministic: the same triangles and options give the same tree.
  static KdTree build(std::span<const Triangle> triangles, const KdBuildOptions& options = {});
  // A tree given node by node (tests, hand-made trees): nodes in pre-order as
  // nodes() describes them; statistics are computed, costs are not.
  static KdTree from_nodes(std::vector<KdNode> nodes, std::vector<std::uint32_t> primitives,
                           const Bounds& bounds);

  // Nodes in pre-order with the left child next (index 0 is the root), so a
  // node's index is its depth-first layout slot.
  const std::vector<KdNode>& nodes() const { return nodes_; }
  // Triangle indices referenced by the leaves.
  const std::vector<std::uint32_t>& primitives() const { return primitives_; }
  // The root box: the triangles' bounds (empty for an empty scene).
  const Bounds& bounds() const { return bounds_; }
  const KdTreeStats& stats() const { return stats_; }

 private:
  std::vector<KdNode> nodes_;
  std::vector<std::uint32_t> primitives_;
  Bounds bounds_;
  KdTreeStats stats_;
  void compute_stats();
  // The statistics of the nodes of `parts` together (a tree's nodes, or the pieces it is made of).
  void compute_stats(std::span<const std::span<const KdNode>> parts);
  friend class KdTreeBuilder;
  friend struct TreeCacheCodec;  // stores and restores every member (tree_cache_file)
};

// Bounds of the part of `triangle` inside `box` (Sutherland-Hodgman clipping);
// empty when they do not meet. Coordinates on a box face are exactly the face.
Bounds clip_triangle_to_box(const Triangle& triangle, const Bounds& box);

}  // namespace nodetrace::tracer
