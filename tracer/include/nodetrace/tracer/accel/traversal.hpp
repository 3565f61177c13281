// Kd-tree traversal that records its node fetches: each ray walks the tree
// front to back with a stack, and every node it visits is one record at the
// node's address in the layout (docs/ARCHITECTURE.md "What a traversal fetches"), with
// leaf primitive-list and triangle reads as the stream selection asks.
#pragma once

#include <cstdint>
#include <vector>

#include "nodetrace/formats/record/record.hpp"
#include "nodetrace/tracer/accel/kdtree.hpp"
#include "nodetrace/tracer/accel/layout.hpp"
#include "nodetrace/tracer/accel/ray_traversal.hpp"
#include "nodetrace/tracer/geometry/ray.hpp"
#include "nodetrace/tracer/render/render_stats.hpp"
#include "nodetrace/tracer/scene/scene.hpp"

namespace nodetrace::tracer {

// Which records a traversal writes: node fetches (tag = level), leaf
// primitive-list reads (tag p), triangle reads (tag t).
struct StreamSelection {
  bool nodes = true, lists = false, triangles = false;
};

struct AddressMap {
  std::uint64_t node_base = 0;
  std::uint32_t node_size = 8;
  std::uint64_t list_base = 0x40000000;  // 4-byte triangle indices of leaves
  std::uint32_t list_entry_size = 4;
  std::uint64_t triangle_base = 0x80000000;  // three vertices of 3 floats each
  std::uint32_t triangle_size = 36;
};

class Traversal : public RayTraversal {
 public:
  // Keeps references to the triangles and the tree; they must outlive it.
  // Throws std::invalid_argument when the layout is not the tree's or the
  // tree is not in pre-order.
  Traversal(const std::vector<Triangle>& triangles, const KdTree& tree, const Layout& layout,
            const StreamSelection& streams, const AddressMap& addresses);

  // One traversal each, appending its records to `records` when not null
  // and adding its counts to `stats` when not null.
  bool closest_hit(const Ray& ray, float t_max, Hit& hit, std::vector<formats::Record>* records,
                   RenderStats* stats) const override;
  bool any_hit(const Ray& ray, float t_max, std::vector<formats::Record>* records,
               RenderStats* stats) const override;

 private:
  // Recording: records is not null (a walk that records nothing is compiled
  // without the recording, for speed). Octant: the ray direction's sign bits
  // (bit a set: negative on axis a, -0 included), a compile-time constant so
  // each interior step knows its near child without a compare; `walk` picks
  // the instance for the ray.
  template <bool AnyHit, bool Recording, unsigned Octant>
  bool traverse(const Ray& ray, float t_max, Hit& hit, std::vector<formats::Record>* records,
                RenderStats* stats) const;
  template <bool AnyHit, bool Recording>
  bool walk(const Ray& ray, float t_max, Hit& hit, std::vector<formats::Record>* records,
            RenderStats* stats) const;

  std::vector<Triangle> listed_triangles_;  // in leaf-list order, for the leaf visits
  const KdTree& tree_;
  StreamSelection streams_;
  AddressMap addresses_;
  // What traversal reads of a node, 8 bytes: interior nodes keep the split
  // and (right child << 2 | axis), the left child being next in pre-order;
  // leaves keep the first primitive and (count << 2 | 3).
  struct CompactNode {
    union {
      float split;
      std::uint32_t first;
    };
    std::uint32_t bits;
  };
  std::vector<CompactNode> compact_;
  std::vector<formats::Record> node_records_;  // the fetch record of each node
};

}  // namespace nodetrace::tracer
