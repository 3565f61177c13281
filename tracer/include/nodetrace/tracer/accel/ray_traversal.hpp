// What the renderer asks of any acceleration structure: one traversal per
// ray, recording the node fetches it makes. The kd-tree's Traversal and the
// BVHs' BvhTraversal implement it.
#pragma once

#include <vector>

#include "nodetrace/formats/record/record.hpp"
#include "nodetrace/tracer/geometry/ray.hpp"
#include "nodetrace/tracer/render/render_stats.hpp"

namespace nodetrace::tracer {

class RayTraversal {
 public:
  virtual ~RayTraversal() = default;
  // One traversal each, appending its records to `records` when not null
  // and adding its counts to `stats` when not null.
  virtual bool closest_hit(const Ray& ray, float t_max, Hit& hit, std::vector<formats::Record>* records,
                           RenderStats* stats) const = 0;
  virtual bool any_hit(const Ray& ray, float t_max, std::vector<formats::Record>* records,
                       RenderStats* stats) const = 0;
};

}  // namespace nodetrace::tracer
