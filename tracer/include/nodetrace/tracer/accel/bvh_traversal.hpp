// BVH traversal as ray-tracing hardware does it, recording its node fetches:
// each visit fetches the whole node (one record of the node's size, tagged
// with its level), tests every child box, and visits the children hit
// nearest first (a stack; a pushed child is read only when popped and its
// entry distance is still nearer than the closest hit). Shadow rays stop at
// the first hit. Leaf triangles are read as the kd-tree's are (streams
// lists and triangles).
#pragma once

#include <cstdint>
#include <vector>

#include "nodetrace/formats/record/record.hpp"
#include "nodetrace/tracer/accel/bvh.hpp"
#include "nodetrace/tracer/accel/layout.hpp"
#include "nodetrace/tracer/accel/ray_traversal.hpp"
#include "nodetrace/tracer/accel/traversal.hpp"

namespace nodetrace::tracer {

class BvhTraversal : public RayTraversal {
 public:
  // Keeps references to the triangles and the BVH; they must outlive it.
  // Throws std::invalid_argument when the layout is not the BVH's.
  BvhTraversal(const std::vector<Triangle>& triangles, const Bvh& bvh, const Layout& layout,
               const StreamSelection& streams, const AddressMap& addresses);

  bool closest_hit(const Ray& ray, float t_max, Hit& hit, std::vector<formats::Record>* records,
                   RenderStats* stats) const override;
  bool any_hit(const Ray& ray, float t_max, std::vector<formats::Record>* records,
               RenderStats* stats) const override;

 private:
  // What traversal reads of a node of arity W: its children's boxes plane
  // by plane, so the W box tests run as one loop, and their references.
  template <unsigned W>
  struct WideNode {
    float lo[3][W], hi[3][W];
    std::uint32_t index[W], count[W];
    std::uint32_t child_count;
  };
  template <unsigned W>
  void fill(std::vector<WideNode<W>>& wide) const;
  template <bool AnyHit>
  bool dispatch(const Ray& ray, float t_max, Hit& hit, std::vector<formats::Record>* records,
                RenderStats* stats) const;
  template <bool AnyHit, unsigned W>
  bool traverse(const std::vector<WideNode<W>>& wide, const Ray& ray, float t_max, Hit& hit,
                std::vector<formats::Record>* records, RenderStats* stats) const;

  std::vector<Triangle> listed_triangles_;  // in leaf-list order, for the leaf visits
  const Bvh& bvh_;
  StreamSelection streams_;
  AddressMap addresses_;
  std::vector<formats::Record> node_records_;  // the fetch record of each node
  // The nodes for traversal; only the one of the tree's arity is filled.
  std::vector<WideNode<2>> nodes2_;
  std::vector<WideNode<4>> nodes4_;
  std::vector<WideNode<8>> nodes8_;
};

}  // namespace nodetrace::tracer
