// The last step of the kd-tree build: the builders' nodes put together in
// the tree's vectors.
#pragma once

#include <algorithm>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <utility>
#include <vector>

#include "accel/kdtree_built_nodes.hpp"
#include "accel/kdtree_events.hpp"
#include "accel/task_pool.hpp"
#include "nodetrace/base/huge_pages.hpp"
#include "nodetrace/tracer/accel/kdtree.hpp"

namespace nodetrace::tracer::kd_build {

// Puts the builders' nodes together in the tree's vectors, in pre-order:
// each builder's nodes are copied once, in chunks, on the pool's threads.
class TreeAssembly {
 public:
  explicit TreeAssembly(const BuiltNodes& root) : root_(root) { place(root, 0, 0); }

  // Every builder's nodes.
  void copy_into(std::vector<KdNode>& nodes, std::vector<std::uint32_t>& primitives, TaskPool& pool) const {
    base::reserve_touched_on_huge_pages(nodes, root_.total_nodes(), pool.threads());
    base::reserve_touched_on_huge_pages(primitives, root_.total_primitives(), pool.threads());
    nodes.resize(root_.total_nodes());
    primitives.resize(root_.total_primitives());
    std::vector<std::unique_ptr<TaskPool::Task>> copies;
    for (const Placement& placement : placements_) {
      copies.push_back(std::make_unique<TaskPool::Task>(
          [&](unsigned) { copy_primitives(placement, primitives); }));
      for (std::size_t first = 0; first < placement.part->nodes.size(); first += kNodesPerCopy) {
        const std::size_t last = std::min(first + kNodesPerCopy, placement.part->nodes.size());
        copies.push_back(std::make_unique<TaskPool::Task>(
            [&, first, last](unsigned) { copy_nodes(placement, first, last, nodes); }));
      }
    }
    for (auto& copy : copies) pool.offer(*copy);
    // The other threads take the oldest; this one the newest.
    for (auto copy = copies.rbegin(); copy != copies.rend(); ++copy) {
      if (pool.take_back(**copy)) {
        (*copy)->run(0);
      } else {
        pool.wait(**copy, 0);
      }
    }
  }

  // The expected cost of a ray through the root box: each interior node's
  // traversal and each leaf's tests, weighted by the node box's area (the
  // builders' terms), summed in pre-order.
  double sah_cost(const Bounds& root_box) const {
    if (root_.nodes.empty() || root_box.empty() || !(surface_area(root_box) > 0)) return 0;
    return add_costs(root_, 0.0);
  }

 private:
  // Where one builder's nodes go.
  struct Placement {
    const BuiltNodes* part;
    std::size_t node_base, primitive_base;  // where its first node and primitive go
    // Per spliced subtree, the nodes and primitives of those before it (one more: all).
    std::vector<std::size_t> spliced_nodes_before, spliced_primitives_before;
    std::vector<std::pair<std::uint32_t, std::size_t>> spliced_roots;  // (parent, root's place), by parent
  };

  void place(const BuiltNodes& part, std::size_t node_base, std::size_t primitive_base) {
    Placement placement{&part, node_base, primitive_base, {0}, {0}, {}};
    for (const SplicedSubtree& subtree : part.spliced) {
      placement.spliced_nodes_before.push_back(placement.spliced_nodes_before.back() + subtree.part->total_nodes());
      placement.spliced_primitives_before.push_back(placement.spliced_primitives_before.back() +
                                                    subtree.part->total_primitives());
    }
    std::vector<std::pair<std::size_t, std::size_t>> subtree_bases;
    for (std::size_t k = 0; k < part.spliced.size(); ++k) {
      const SplicedSubtree& subtree = part.spliced[k];
      const std::size_t root = node_base + subtree.nodes_before + placement.spliced_nodes_before[k];
      placement.spliced_roots.emplace_back(subtree.parent, root);
      subtree_bases.emplace_back(root, primitive_base + subtree.primitives_before +
                                           placement.spliced_primitives_before[k]);
    }
    std::sort(placement.spliced_roots.begin(), placement.spliced_roots.end());
    placements_.push_back(std::move(placement));
    for (std::size_t k = 0; k < part.spliced.size(); ++k) {
      place(*part.spliced[k].part, subtree_bases[k].first, subtree_bases[k].second);
    }
  }

  // How many of the part's spliced subtrees come before its own node `index`.
  static std::size_t spliced_before(const BuiltNodes& part, std::uint32_t index) {
    return static_cast<std::size_t>(
        std::upper_bound(part.spliced.begin(), part.spliced.end(), index,
                         [](std::uint32_t i, const SplicedSubtree& subtree) { return i < subtree.nodes_before; }) -
        part.spliced.begin());
  }

  static void copy_nodes(const Placement& placement, std::size_t first, std::size_t last, std::vector<KdNode>& nodes) {
    const BuiltNodes& part = *placement.part;
    auto place_of = [&](std::uint32_t index) {
      return static_cast<std::uint32_t>(placement.node_base + index +
                                        placement.spliced_nodes_before[spliced_before(part, index)]);
    };
    std::size_t before = spliced_before(part, static_cast<std::uint32_t>(first));
    for (std::size_t i = first; i < last; ++i) {
      while (before < part.spliced.size() && part.spliced[before].nodes_before <= i) ++before;
      const BuiltNode& built = part.nodes[i];
      KdNode node;
      node.level = built.level;
      node.axis = built.axis;
      if (built.is_leaf()) {
        node.first = static_cast<std::uint32_t>(placement.primitive_base + built.split_or_first +
                                                placement.spliced_primitives_before[before]);
        node.count = built.right_or_count;
      } else {
        node.split = std::bit_cast<float>(built.split_or_first);
        node.left = place_of(static_cast<std::uint32_t>(i + 1));
        node.right = built.right_or_count;
        if (node.right == kSplicedRoot) {
          const auto root = std::lower_bound(placement.spliced_roots.begin(), placement.spliced_roots.end(),
                                             std::pair{static_cast<std::uint32_t>(i), std::size_t{0}});
          node.right = static_cast<std::uint32_t>(root->second);
        } else {
          node.right = place_of(node.right);
        }
      }
      nodes[placement.node_base + i + placement.spliced_nodes_before[before]] = node;
    }
  }

  static void copy_primitives(const Placement& placement, std::vector<std::uint32_t>& primitives) {
    const BuiltNodes& part = *placement.part;
    std::size_t from = 0;
    for (std::size_t k = 0; k <= part.spliced.size(); ++k) {
      const std::size_t to = k < part.spliced.size() ? part.spliced[k].primitives_before : part.primitives.size();
      std::uint32_t* out = primitives.data() + placement.primitive_base + placement.spliced_primitives_before[k];
      for (std::size_t i = from; i < to; ++i) out[i] = part.primitives[i];
      from = to;
    }
  }

  // `sum` plus the part's terms in pre-order, its spliced subtrees' among its own.
  static double add_costs(const BuiltNodes& part, double sum) {
    std::size_t from = 0;
    for (std::size_t k = 0; k <= part.spliced.size(); ++k) {
      const std::size_t to = k < part.spliced.size() ? part.spliced[k].nodes_before : part.nodes.size();
      for (std::size_t i = from; i < to; ++i) sum += part.costs[i];
      if (k < part.spliced.size()) sum = add_costs(*part.spliced[k].part, sum);
      from = to;
    }
    return sum;
  }

  static constexpr std::size_t kNodesPerCopy = std::size_t{1} << 15;

  const BuiltNodes& root_;
  std::vector<Placement> placements_;  // in pre-order
};

}  // namespace nodetrace::tracer::kd_build
