// What every traversal does at a leaf: test its triangles in order,
// recording the reads the stream selection asks for. Internal header.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "accel/watertight_intersection.hpp"
#include "nodetrace/base/huge_pages.hpp"
#include "nodetrace/formats/record/record.hpp"
#include "nodetrace/tracer/accel/traversal.hpp"

namespace nodetrace::tracer::detail {

// The triangles in leaf-list order (the one at slot i is primitives[i]'s):
// a leaf's triangles lie side by side, read without an indirection.
inline std::vector<Triangle> triangles_in_list_order(const std::vector<Triangle>& triangles,
                                                     const std::vector<std::uint32_t>& primitives) {
  std::vector<Triangle> ordered;
  base::reserve_on_huge_pages(ordered, primitives.size());
  for (const std::uint32_t id : primitives) ordered.push_back(triangles[id]);
  return ordered;
}

// The triangles a kd-tree ray has tested lately: a triangle straddling
// splits sits in several leaves, and testing it again for the same ray
// cannot change the answer (a miss stays a miss as the closest hit so far
// only shrinks; a hit is the closest already or was passed over), so the
// test is skipped. Its records are still made and its test still counted:
// the modelled traversal tests it, only the simulator does not repeat the
// arithmetic. The last 8 ids, a ring: a miss here only costs a test.
class TestedTriangles {
 public:
  bool contains(std::uint32_t id) const {
    bool seen = false;
    for (const std::uint32_t tested : ids_) seen |= tested == id;
    return seen;
  }
  void add(std::uint32_t id) { ids_[next_++ % ids_.size()] = id; }

 private:
  std::array<std::uint32_t, 8> ids_ = {kNone, kNone, kNone, kNone, kNone, kNone, kNone, kNone};
  static constexpr std::uint32_t kNone = ~std::uint32_t{0};  // never a triangle's id
  std::uint32_t next_ = 0;
};

// A BVH leaf holds each triangle once: nothing to remember.
struct NoTestedTriangles {
  static bool contains(std::uint32_t) { return false; }
  static void add(std::uint32_t) {}
};

struct LeafVisit {
  const std::vector<Triangle>& listed_triangles;  // triangles_in_list_order
  const std::vector<std::uint32_t>& primitives;
  const ShearedRay& sheared;
  const StreamSelection& streams;
  const AddressMap& map;
  std::vector<formats::Record>* records;

  // Tests primitives()[first, first + count): a list entry read (tag p) and
  // a triangle read (tag t) per triangle when selected; a hit nearer than
  // `best` becomes `hit` and `best`. Returns whether one was hit; an any-hit
  // visit stops at the first. `tested` skips the triangles the ray has
  // tested in an earlier leaf.
  template <bool AnyHit, class Tested>
  bool visit(std::uint32_t first, std::uint32_t count, float& best, Hit& hit, std::uint64_t& tests,
             Tested& tested) const {
    bool found = false;
    for (std::uint32_t i = 0; i < count; ++i) {
      const std::uint32_t slot = first + i;
      const std::uint32_t id = primitives[slot];
      if (records && streams.lists) {
        records->push_back({.address = map.list_base + std::uint64_t{slot} * map.list_entry_size,
                            .size = map.list_entry_size,
                            .type = formats::AccessType::Read,
                            .tag = formats::kTagPrimitiveList});
      }
      if (records && streams.triangles) {
        records->push_back({.address = map.triangle_base + std::uint64_t{id} * map.triangle_size,
                            .size = map.triangle_size,
                            .type = formats::AccessType::Read,
                            .tag = formats::kTagTriangle});
      }
      ++tests;
      if (tested.contains(id)) continue;
      tested.add(id);
      if (intersect_sheared(sheared, listed_triangles[slot], best, hit)) {
        best = hit.t;
        hit.triangle = id;
        found = true;
        if constexpr (AnyHit) break;
      }
    }
    return found;
  }
};

}  // namespace nodetrace::tracer::detail
