#include "nodetrace/tracer/accel/acceleration_structure.hpp"

#include "nodetrace/tracer/accel/bvh_traversal.hpp"

namespace nodetrace::tracer {

namespace {
constexpr AccelKind kAllKinds[] = {AccelKind::KdTree, AccelKind::Bvh2, AccelKind::Bvh4, AccelKind::Bvh8,
                                   AccelKind::CwBvh8};
}  // namespace

std::string_view accel_name(AccelKind kind) {
  switch (kind) {
    case AccelKind::KdTree: return "kdtree";
    case AccelKind::Bvh2: return "bvh2";
    case AccelKind::Bvh4: return "bvh4";
    case AccelKind::Bvh8: return "bvh8";
    case AccelKind::CwBvh8: return "cwbvh8";
  }
  return "kdtree";
}

std::optional<AccelKind> parse_accel_name(std::string_view name) {
  for (auto kind : kAllKinds) {
    if (accel_name(kind) == name) return kind;
  }
  return std::nullopt;
}

std::uint32_t default_node_size(AccelKind kind) {
  switch (kind) {
    case AccelKind::KdTree: return 8;
    // Two boxes of 6 floats (48 bytes) and two 4-byte child references with
    // room for their leaf counts: 64 (Aila and Laine 2009).
    case AccelKind::Bvh2: return 64;
    // 4 x 24 bytes of boxes + 4 x 4 of references = 112, padded to 128.
    case AccelKind::Bvh4: return 128;
    // 8 x 24 + 8 x 4 = 224, padded to 256.
    case AccelKind::Bvh8: return 256;
    // Ylitie, Karras and Laine 2017: origin, 3 exponents, masks, 8 x 6
    // quantized planes and child metadata in 80 bytes.
    case AccelKind::CwBvh8: return 80;
  }
  return 8;
}

unsigned accel_arity(AccelKind kind) {
  switch (kind) {
    case AccelKind::Bvh4: return 4;
    case AccelKind::Bvh8:
    case AccelKind::CwBvh8: return 8;
    case AccelKind::KdTree:
    case AccelKind::Bvh2: return 2;
  }
  return 2;
}

AccelerationStructure AccelerationStructure::build(std::span<const Triangle> triangles, AccelKind kind,
                                                   const AccelBuildOptions& options) {
  if (kind == AccelKind::KdTree) return {kind, KdTree::build(triangles, options.kdtree)};
  return {kind, Bvh::build(triangles, accel_arity(kind), kind == AccelKind::CwBvh8, options.bvh)};
}

const Bounds& AccelerationStructure::bounds() const {
  return std::visit([](const auto& tree) -> const Bounds& { return tree.bounds(); }, tree_);
}

const KdTreeStats& AccelerationStructure::stats() const {
  return std::visit([](const auto& tree) -> const KdTreeStats& { return tree.stats(); }, tree_);
}

TreeShape AccelerationStructure::shape() const {
  if (const KdTree* tree = kdtree()) return kdtree_shape(*tree);
  return bvh()->shape();
}

std::unique_ptr<RayTraversal> AccelerationStructure::traversal(const std::vector<Triangle>& triangles,
                                                               const Layout& layout, const StreamSelection& streams,
                                                               const AddressMap& addresses) const {
  if (const KdTree* tree = kdtree()) return std::make_unique<Traversal>(triangles, *tree, layout, streams, addresses);
  return std::make_unique<BvhTraversal>(triangles, *bvh(), layout, streams, addresses);
}

}  // namespace nodetrace::tracer
