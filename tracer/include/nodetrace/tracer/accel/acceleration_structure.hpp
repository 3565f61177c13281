// The one interface to the tracer's acceleration structures: the SAH
// kd-tree (the paper's, the default) and the BVHs. Each is built from a
// scene's triangles, describes its shape for the layouts, and makes the
// traversal the renderer calls for every ray.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string_view>
#include <variant>
#include <vector>

#include "nodetrace/tracer/accel/bvh.hpp"
#include "nodetrace/tracer/accel/kdtree.hpp"
#include "nodetrace/tracer/accel/layout.hpp"
#include "nodetrace/tracer/accel/ray_traversal.hpp"
#include "nodetrace/tracer/accel/traversal.hpp"

namespace nodetrace::tracer {

enum class AccelKind : std::uint8_t {
  KdTree,  // SAH kd-tree, 8-byte nodes
  Bvh2,    // binary BVH, 64-byte nodes: two child boxes and references
  Bvh4,    // 4-wide BVH, 128-byte nodes: four full-precision boxes and references
  Bvh8,    // 8-wide BVH, 256-byte nodes: eight full-precision boxes and references
  CwBvh8,  // compressed 8-wide BVH, 80-byte nodes: quantized child boxes
};

std::string_view accel_name(AccelKind kind);
std::optional<AccelKind> parse_accel_name(std::string_view name);
// Bytes of one node as the structure stores it (--node-size overrides it).
std::uint32_t default_node_size(AccelKind kind);
// Children per node: 2 for the kd-tree and the binary BVH.
unsigned accel_arity(AccelKind kind);

struct AccelBuildOptions {
  KdBuildOptions kdtree;
  BvhBuildOptions bvh;
};

class AccelerationStructure {
 public:
  // Deterministic: the same triangles and options give the same structure.
  static AccelerationStructure build(std::span<const Triangle> triangles, AccelKind kind,
                                     const AccelBuildOptions& options = {});

  AccelKind kind() const { return kind_; }
  const Bounds& bounds() const;
  // The tree's figures (a BVH's as Bvh::stats describes them).
  const KdTreeStats& stats() const;
  TreeShape shape() const;
  // The traversal the renderer calls; it keeps references to `triangles`
  // and to this structure. Throws std::invalid_argument when the layout is
  // not this structure's.
  std::unique_ptr<RayTraversal> traversal(const std::vector<Triangle>& triangles, const Layout& layout,
                                          const StreamSelection& streams, const AddressMap& addresses) const;

  const KdTree* kdtree() const { return std::get_if<KdTree>(&tree_); }
  const Bvh* bvh() const { return std::get_if<Bvh>(&tree_); }

 private:
  AccelerationStructure(AccelKind kind, std::variant<KdTree, Bvh> tree) : kind_(kind), tree_(std::move(tree)) {}
  AccelKind kind_;
  std::variant<KdTree, Bvh> tree_;
  friend struct TreeCacheCodec;  // makes a loaded structure (tree_cache_file)
};

}  // namespace nodetrace::tracer
