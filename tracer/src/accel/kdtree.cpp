#include "nodetrace/tracer/accel/kdtree.hpp"

#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include "accel/kdtree_assembly.hpp"
#include "accel/kdtree_builder.hpp"
#include "accel/kdtree_events.hpp"
#include "accel/task_pool.hpp"
#include "nodetrace/base/portable_math.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <ctime>
#include <stdexcept>
#include <utility>

namespace nodetrace::tracer {

// The same results on every machine (portable_math.hpp).
namespace math = base::portable_math;

int default_max_depth(std::size_t triangle_count) {
  if (triangle_count < 2) return 8;
  return 8 + static_cast<int>(std::lround(1.3 * math::log2(static_cast<double>(triangle_count))));
}

Bounds clip_triangle_to_box(const Triangle& triangle, const Bounds& box) {
  // Up to 3 + 6 vertices after clipping a triangle by six planes.
  std::array<std::array<Vec3, 10>, 2> buffers;
  Vec3* polygon = buffers[0].data();
  Vec3* clipped = buffers[1].data();
  polygon[0] = triangle.v0;
  polygon[1] = triangle.v1;
  polygon[2] = triangle.v2;
  std::size_t count = 3;
  for (int axis = 0; axis < 3 && count > 0; ++axis) {
    for (int face = 0; face < 2 && count > 0; ++face) {
      const float plane = face == 0 ? box.lo[axis] : box.hi[axis];
      // Inside: >= plane for the low face, <= plane for the high face.
      auto inside = [&](const Vec3& p) { return face == 0 ? p[axis] >= plane : p[axis] <= plane; };
      // A plane with every vertex inside leaves the polygon as it is.
      if (std::all_of(polygon, polygon + count, inside)) continue;
      std::size_t out = 0;
      for (std::size_t i = 0; i < count; ++i) {
        const Vec3& a = polygon[i];
        const Vec3& b = polygon[i + 1 == count ? 0 : i + 1];
        const bool a_in = inside(a), b_in = inside(b);
        if (a_in) clipped[out++] = a;
        if (a_in != b_in) {
          const float t = (plane - a[axis]) / (b[axis] - a[axis]);
          Vec3 p = a + (b - a) * t;
          p[axis] = plane;  // exactly on the face, so the clipped box ends there
          clipped[out++] = p;
        }
      }
      count = out;
      std::swap(polygon, clipped);
    }
  }
  Bounds result;
  for (std::size_t i = 0; i < count; ++i) result.extend(polygon[i]);
  if (!result.empty()) {
    // Rounding in the lerp may step just outside on the other axes.
    result.lo = max(result.lo, box.lo);
    result.hi = min(result.hi, box.hi);
  }
  return result;
}

KdTree KdTree::build(std::span<const Triangle> triangles, const KdBuildOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  const std::clock_t cpu_start = std::clock();
  if (triangles.size() > kd_build::kTriangleMask) {
    throw std::length_error("kd-tree build: more than 2^30 triangles");
  }
  KdTree tree;
  for (const auto& t : triangles) {
    tree.bounds_.extend(t.v0);
    tree.bounds_.extend(t.v1);
    tree.bounds_.extend(t.v2);
  }
  int max_depth = options.max_depth > 0 ? options.max_depth : default_max_depth(triangles.size());
  max_depth = std::min(max_depth, kMaxLevelLimit);  // traversal stacks are sized for it
  {
    TaskPool pool(kd_build::build_threads(options.threads, triangles.size()));
    kd_build::BuiltNodes built = kd_build::build_nodes(triangles, options, max_depth, tree.bounds_, pool);
    const kd_build::TreeAssembly assembly(built);
    tree.stats_.sah_cost = assembly.sah_cost(tree.bounds_);
    kd_build::release_costs(built);
    // The builders' nodes become the tree's KdNodes (twice their size), then
    // are freed: the parts and the tree are the build's high-water mark.
    // The events freed during the build stay in the allocator's arenas,
    // resident, unless handed back to the system first.
#if defined(__GLIBC__)
    malloc_trim(0);
#endif
    assembly.copy_into(tree.nodes_, tree.primitives_, pool);
  }
  tree.compute_stats();
  tree.stats_.depth_limit = max_depth;
  tree.stats_.build_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  tree.stats_.build_cpu_seconds = double(std::clock() - cpu_start) / CLOCKS_PER_SEC;
  return tree;
}

KdTree KdTree::from_nodes(std::vector<KdNode> nodes, std::vector<std::uint32_t> primitives,
                          const Bounds& bounds) {
  KdTree tree;
  tree.nodes_ = std::move(nodes);
  tree.primitives_ = std::move(primitives);
  tree.bounds_ = bounds;
  tree.compute_stats();
  return tree;
}

void KdTree::compute_stats() {
  const std::span<const KdNode> all(nodes_);
  compute_stats({&all, 1});
}

void KdTree::compute_stats(std::span<const std::span<const KdNode>> parts) {
  KdTreeStats& s = stats_;
  s.nodes = s.interior = s.leaves = s.empty_leaves = s.primitive_references = 0;
  s.nodes_per_level.clear();
  s.depth = 0;
  for (const auto& part : parts) {
    s.nodes += part.size();
    for (const KdNode& node : part) {
      if (node.level >= s.nodes_per_level.size()) s.nodes_per_level.resize(node.level + 1, 0);
      ++s.nodes_per_level[node.level];
      s.depth = std::max<std::uint32_t>(s.depth, node.level);
      if (node.is_leaf()) {
        ++s.leaves;
        if (node.count == 0) ++s.empty_leaves;
        s.primitive_references += node.count;
      } else {
        ++s.interior;
      }
    }
  }
  if (s.leaves > 0) s.mean_leaf_size = double(s.primitive_references) / double(s.leaves);
  if (s.leaves > s.empty_leaves) {
    s.mean_nonempty_leaf_size = double(s.primitive_references) / double(s.leaves - s.empty_leaves);
  }
}

}  // namespace nodetrace::tracer
