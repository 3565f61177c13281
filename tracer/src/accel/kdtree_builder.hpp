// The kd-tree's SAH builders: one per thread of the build's task pool, each
// splitting nodes depth-first and offering right children to the others.
#pragma once

#include <cstddef>
#include <span>

#include "accel/kdtree_built_nodes.hpp"
#include "accel/task_pool.hpp"
#include "nodetrace/tracer/accel/kdtree.hpp"

namespace nodetrace::tracer::kd_build {

// Threads for a build: no more than could each get a subtree offered, so a
// small scene starts none.
unsigned build_threads(unsigned requested, std::size_t triangle_count);

// The nodes of the tree over `triangles` (bounded by `root_box`), built by a
// builder per thread of `pool`.
BuiltNodes build_nodes(std::span<const Triangle> triangles, const KdBuildOptions& options, int max_depth,
                       const Bounds& root_box, TaskPool& pool);

}  // namespace nodetrace::tracer::kd_build
