#include "accel/kdtree_builder.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <limits>
#include <memory>
#include <numeric>
#include <stdexcept>
#include <thread>
#include <utility>

#include "accel/kdtree_events.hpp"
#include "nodetrace/base/huge_pages.hpp"

namespace nodetrace::tracer::kd_build {

namespace {

struct SplitChoice {
  double cost = std::numeric_limits<double>::infinity();
  float position = 0;
  int axis = -1;
  bool planar_left = true;
};

// Lists a builder has done with, for its next nodes: the build allocates
// (and the system zeroes) far less. Depth-first, few are spare at a time;
// long lists, from the few nodes near the root, are freed.
template <typename List>
class SpareVectors {
 public:
  static constexpr std::size_t kLongest = std::size_t{1} << 15;
  List take() {
    if (spare_.empty()) return {};
    List list = std::move(spare_.back());
    spare_.pop_back();
    return list;
  }
  void give(List&& list) {
    if (list.capacity() > kLongest) {
      // Freed now: the caller's node, whose list it was, lives on until its
      // subtree is built, and so would the list.
      List().swap(list);
      return;
    }
    list.clear();
    spare_.push_back(std::move(list));
  }

 private:
  std::vector<List> spare_;
};

// What one node's build starts from.
struct NodeInput {
  NodeEvents events;
  std::vector<std::uint32_t> ids;  // its triangles, ascending
  Bounds box;
  int level = 0;
  int unproductive = 0;  // unproductive splits on its path (KdTreeBuilder::unproductive_for)
};

// A right child of fewer triangles (or a left one, which keeps its builder
// busy meanwhile) is not worth offering to other threads.
constexpr std::size_t kMinTrianglesPerTask = 512;
// Nodes of fewer triangles sweep their axes on one thread.
constexpr std::size_t kMinTrianglesPerAxisTask = std::size_t{1} << 15;

Bounds triangle_bounds(const Triangle& triangle) {
  Bounds box;
  box.extend(triangle.v0);
  box.extend(triangle.v1);
  box.extend(triangle.v2);
  return box;
}

}  // namespace

// Threads for a build: no more than could each get a subtree offered, so a
// small scene starts none.
unsigned build_threads(unsigned requested, std::size_t triangle_count) {
  const unsigned threads = requested > 0 ? requested : std::max(1u, std::thread::hardware_concurrency());
  return static_cast<unsigned>(std::clamp<std::size_t>(triangle_count / kMinTrianglesPerTask, 1, threads));
}

// Builds subtrees on one thread of the tree's task pool. The tree has a
// builder per pool thread: a builder splitting a node offers the right child
// to the others while it builds the left; a builder that took it builds it
// into a fragment of its own, which the owner splices in after the left
// subtree, so the nodes are in pre-order whoever built them.
class KdTreeBuilder {
 public:
  using Builders = std::vector<std::unique_ptr<KdTreeBuilder>>;

  KdTreeBuilder(std::span<const Triangle> triangles, const KdBuildOptions& options, int max_depth,
                double root_area, TaskPool& pool, const Builders& builders, unsigned thread)
      : triangles_(triangles),
        options_(options),
        max_depth_(max_depth),
        root_area_(root_area),
        pool_(pool),
        builders_(builders),
        thread_(thread),
        side_(triangles.size(), kBoth) {}

  // Builds the whole tree over `root_box` (the triangles' bounds), from the pool's own thread.
  BuiltNodes build_tree(const Bounds& root_box) {
    BuiltNodes tree;
    output_ = &tree;
    NodeInput root;
    root.box = root_box;
    base::reserve_on_huge_pages(root.ids, triangles_.size());
    root.ids.resize(triangles_.size());
    std::iota(root.ids.begin(), root.ids.end(), std::uint32_t{0});
    // A flat triangle has one event on an axis, any other two.
    std::array<std::size_t, 3> counts{};
    for (const auto& t : triangles_) {
      const Bounds box = triangle_bounds(t);
      for (int axis = 0; axis < 3; ++axis) counts[axis] += box.lo[axis] == box.hi[axis] ? 1 : 2;
    }
    NodeEvents& events = root.events;
    events.begin = {0, counts[0], counts[0] + counts[1], counts[0] + counts[1] + counts[2]};
    base::reserve_on_huge_pages(events.events, events.begin[3]);
    events.events.resize(events.begin[3]);
    // The three axes' events are made and sorted apart, on other threads when free.
    for_each_axis([&](int axis) {
      Event* next = events.events.data() + events.begin[axis];
      for (std::uint32_t i = 0; i < triangles_.size(); ++i) {
        const Bounds box = triangle_bounds(triangles_[i]);
        if (box.lo[axis] == box.hi[axis]) {
          *next++ = {box.lo[axis], kPlanar << kTriangleBits | i};
        } else {
          *next++ = {box.lo[axis], kStart << kTriangleBits | i};
          *next++ = {box.hi[axis], kEnd << kTriangleBits | i};
        }
      }
      EventList buffer;
      sort_events({events.events.data() + events.begin[axis], events.events.data() + events.begin[axis + 1]}, buffer);
    });
    build_node(std::move(root));
    output_ = nullptr;
    return tree;
  }

 private:
  // Runs job(axis) for the three axes, offering the first two to other threads.
  template <typename Job>
  void for_each_axis(const Job& job) {
    if (pool_.threads() == 1) {
      for (int axis = 0; axis < 3; ++axis) job(axis);
      return;
    }
    TaskPool::Task first([&](unsigned) { job(0); }), second([&](unsigned) { job(1); });
    pool_.offer(first);
    pool_.offer(second);
    job(2);
    for (auto [task, axis] : {std::pair{&second, 1}, std::pair{&first, 0}}) {
      if (pool_.take_back(*task)) {
        job(axis);
      } else {
        pool_.wait(*task, thread_);
      }
    }
  }

  // The best split: the cheapest plane, the first in sweep order (axis,
  // then position) among equals. The axes of a large node are swept on
  // other threads too, each apart, which chooses the same plane.
  SplitChoice find_split(const NodeInput& node) {
    if (node.ids.size() >= kMinTrianglesPerAxisTask && pool_.threads() > 1) {
      std::array<SplitChoice, 3> per_axis;
      for_each_axis([&](int axis) { per_axis[axis] = sweep_axis(node, axis, SplitChoice{}); });
      SplitChoice best = per_axis[0];
      for (int axis = 1; axis < 3; ++axis) {
        if (per_axis[axis].cost < best.cost) best = per_axis[axis];
      }
      return best;
    }
    SplitChoice best;
    for (int axis = 0; axis < 3; ++axis) best = sweep_axis(node, axis, best);
    return best;
  }

  // The better of `best` and the cheapest plane on `axis` (the first among
  // equals, `best` before them all).
  SplitChoice sweep_axis(const NodeInput& node, int axis, SplitChoice best) const {
    const Bounds& box = node.box;
    const double area = surface_area(box);
    if (!(area > 0)) return best;
    const double kt = options_.traversal_cost, ki = options_.intersection_cost;
    const double bonus = 1.0 - options_.empty_bonus;
    // A cost estimate with a multiplication for the divisions is within a
    // few units in the last place of the exact cost when no term is
    // negative: a plane whose estimate exceeds the best cost by far more
    // cannot win, so its exact cost (the divisions) is skipped. The choice is
    // the exact sweep's.
    const double inverse_area = 1.0 / area;
    const bool can_estimate = kt >= 0 && ki >= 0 && bonus >= 0;
    constexpr double kEstimateMargin = 1.0 + 1e-9;
    const std::span<const Event> list = node.events.axis(axis);
    const Event* e = list.data();
    const Event* const last = e + list.size();
    std::size_t left = 0, right = node.ids.size();
    while (e != last) {
      const float position = e->position;
      std::size_t ending = 0, planar = 0, starting = 0;
      for (; e != last && e->position == position && e->type() == kEnd; ++e) ++ending;
      for (; e != last && e->position == position && e->type() == kPlanar; ++e) ++planar;
      for (; e != last && e->position == position; ++e) ++starting;
      right -= planar + ending;
      // Planes on the box faces cut nothing off; both children need volume.
      if (position > box.lo[axis] && position < box.hi[axis]) {
        Bounds lbox = box, rbox = box;
        lbox.hi[axis] = position;
        rbox.lo[axis] = position;
        const double left_area = surface_area(lbox), right_area = surface_area(rbox);
        auto cost_of = [&](double pl, double pr, std::size_t nl, std::size_t nr) {
          const double c = kt + ki * (pl * double(nl) + pr * double(nr));
          return (nl == 0 || nr == 0) ? c * bonus : c;
        };
        if (can_estimate) {
          const double pl = left_area * inverse_area, pr = right_area * inverse_area;
          const double estimate =
              std::min(cost_of(pl, pr, left + planar, right), cost_of(pl, pr, left, right + planar));
          if (estimate > best.cost * kEstimateMargin) {
            left += starting + planar;
            continue;
          }
        }
        const double pl = left_area / area, pr = right_area / area;
        auto cost = [&](std::size_t nl, std::size_t nr) { return cost_of(pl, pr, nl, nr); };
        const double with_left = cost(left + planar, right);
        const double with_right = cost(left, right + planar);
        const bool planar_left = with_left <= with_right;
        const double c = planar_left ? with_left : with_right;
        if (c < best.cost) best = {c, position, axis, planar_left};
      }
      left += starting + planar;
    }
    return best;
  }

  std::uint32_t make_leaf(std::uint32_t index, NodeInput&& node) {
    BuiltNode& leaf = output_->nodes[index];
    leaf.axis = KdNode::kLeafAxis;
    leaf.split_or_first = static_cast<std::uint32_t>(output_->primitives.size());
    leaf.right_or_count = static_cast<std::uint32_t>(node.ids.size());
    output_->primitives.append(node.ids.begin(), node.ids.end());
    output_->costs[index] =
        options_.intersection_cost * double(leaf.right_or_count) * surface_area(node.box) / root_area_;
    spare_events_.give(std::move(node.events.events));
    spare_ids_.give(std::move(node.ids));
    return index;
  }

  // Builds the subtree of `node` into this builder's tree; returns the index of its root.
  std::uint32_t build_node(NodeInput&& node) {
    const auto index = static_cast<std::uint32_t>(output_->nodes.size());
    output_->nodes.emplace_back();
    output_->nodes[index].level = static_cast<std::uint16_t>(node.level);
    output_->costs.push_back(0);
    const std::size_t n = node.ids.size();
    if (n == 0 || n <= options_.leaf_size || node.level >= max_depth_ ||
        node.unproductive >= kMaxUnproductiveSplits) {
      return make_leaf(index, std::move(node));
    }
    const SplitChoice split = find_split(node);
    if (split.axis < 0 || split.cost >= options_.intersection_cost * double(n)) {
      return make_leaf(index, std::move(node));
    }
    {
      BuiltNode& interior = output_->nodes[index];
      interior.axis = static_cast<std::uint8_t>(split.axis);
      interior.split_or_first = std::bit_cast<std::uint32_t>(split.position);
      output_->costs[index] = options_.traversal_cost * surface_area(node.box) / root_area_;
    }
    // Named members, not a structured binding: clang before 16 cannot capture one in a lambda (the fuzzers' build).
    std::pair<NodeInput, NodeInput> children = split_node(std::move(node), split);
    NodeInput& left = children.first;
    NodeInput& right = children.second;
    std::uint32_t left_index, right_index;
    if (pool_.threads() > 1 && std::min(left.ids.size(), right.ids.size()) >= kMinTrianglesPerTask) {
      // While this builder builds the left child, an idle one may take the right.
      std::unique_ptr<BuiltNodes> right_part;
      TaskPool::Task right_task([&](unsigned thread) {
        right_part = std::make_unique<BuiltNodes>(builders_[thread]->build_fragment(std::move(right)));
      });
      pool_.offer(right_task);
      left_index = build_node(std::move(left));
      if (pool_.take_back(right_task)) {
        right_index = build_node(std::move(right));
      } else {
        pool_.wait(right_task, thread_);
        right_index = kSplicedRoot;
        splice(index, std::move(right_part));
      }
    } else {
      left_index = build_node(std::move(left));
      right_index = build_node(std::move(right));
    }
    // The left child is the next node (pre-order): only the right is kept.
    if (left_index != index + 1) throw std::logic_error("kd-tree build: a left child is not its parent's next node");
    output_->nodes[index].right_or_count = right_index;
    return index;
  }

  // The children of `node` split at `split`.
  std::pair<NodeInput, NodeInput> split_node(NodeInput&& node, const SplitChoice& split) {
    // Classify: which triangles lie only left, only right, or on both sides.
    for (auto id : node.ids) side_[id] = kBoth;
    for (const Event& e : node.events.axis(split.axis)) {
      const std::uint32_t type = e.type();
      if (type == kEnd && e.position <= split.position) {
        side_[e.triangle()] = kLeftOnly;
      } else if (type == kStart && e.position >= split.position) {
        side_[e.triangle()] = kRightOnly;
      } else if (type == kPlanar) {
        if (e.position < split.position || (e.position == split.position && split.planar_left)) {
          side_[e.triangle()] = kLeftOnly;
        } else {
          side_[e.triangle()] = kRightOnly;
        }
      }
    }

    NodeInput left{.events = {spare_events_.take()}, .ids = spare_ids_.take(), .box = node.box, .level = node.level + 1};
    NodeInput right{.events = {spare_events_.take()}, .ids = spare_ids_.take(), .box = node.box, .level = node.level + 1};
    left.box.hi[split.axis] = split.position;
    right.box.lo[split.axis] = split.position;
    for (auto& list : new_left_) list.clear();
    for (auto& list : new_right_) list.clear();
    for (auto id : node.ids) {
      if (side_[id] == kLeftOnly) {
        left.ids.push_back(id);
      } else if (side_[id] == kRightOnly) {
        right.ids.push_back(id);
      } else {
        // Straddling: clip to each child (perfect splits), new events per side.
        const Bounds l = clip_triangle_to_box(triangles_[id], left.box);
        if (!l.empty()) {
          add_events(new_left_, id, l);
          left.ids.push_back(id);
        }
        const Bounds r = clip_triangle_to_box(triangles_[id], right.box);
        if (!r.empty()) {
          add_events(new_right_, id, r);
          right.ids.push_back(id);
        }
      }
    }
    // At most two events per triangle and axis (and a slot for split_events'
    // last write), nearly all used. The lists of the nodes near the root are
    // fresh memory: its pages are touched by all threads first, as the other
    // threads wait for the first split anyway.
    for (NodeInput* child : {&left, &right}) {
      base::reserve_touched_on_huge_pages(child->events.events, 6 * child->ids.size() + 1, pool_.threads());
      child->events.events.resize(6 * child->ids.size() + 1);
    }
    std::size_t left_size = 0, right_size = 0;
    for (int axis = 0; axis < 3; ++axis) {
      sort_events(new_left_[axis], sort_buffer_);
      sort_events(new_right_[axis], sort_buffer_);
      left.events.begin[axis] = left_size;
      right.events.begin[axis] = right_size;
      split_events(node.events.axis(axis), new_left_[axis], new_right_[axis], left.events.events.data(),
                   left_size, right.events.events.data(), right_size);
    }
    left.events.events.resize(left_size);
    right.events.events.resize(right_size);
    left.events.begin[3] = left.events.events.size();
    right.events.begin[3] = right.events.events.size();
    // Triangle ids stay ascending in every list (filtered in order), so
    // leaves list them in order.
    const std::size_t n = node.ids.size();
    left.unproductive = node.unproductive + unproductive_for(node.box, split, n, left.ids.size(), right.ids.size());
    right.unproductive = node.unproductive + unproductive_for(node.box, split, n, right.ids.size(), left.ids.size());
    spare_events_.give(std::move(node.events.events));  // the parent's lists, for the children's children
    spare_ids_.give(std::move(node.ids));
    return {std::move(left), std::move(right)};
  }

  // In a flat box (zero extent on an axis other than the split's: all the
  // triangles lie in one axis-aligned plane) the SAH charges nothing for a
  // triangle on both sides, since a ray crossing the plane meets only one
  // child. It then keeps splitting
  // overlapping coplanar triangles down to the depth limit, each level
  // copying nearly all of them: exponential time and memory. Such a split
  // counts as unproductive for a child when it sends at least half the
  // parent's triangles to both sides, or leaves the child nearly all of them
  // while the sibling is not empty (no empty space was cut off). A node
  // whose path holds kMaxUnproductiveSplits of them is a leaf, so a flat
  // subtree copies its triangles at most 2^kMaxUnproductiveSplits times.
  // In 3-D boxes the SAH itself prices the copies, and this never applies,
  // so trees of scenes with depth are exactly as before. (Nearly flat boxes
  // are left to the SAH: thin cells in ordinary scenes such as BART Kitchen
  // would change.)
  static int unproductive_for(const Bounds& box, const SplitChoice& split, std::size_t n,
                              std::size_t child, std::size_t sibling) {
    const int a = (split.axis + 1) % 3, b = (split.axis + 2) % 3;
    const double face = (double(box.hi[a]) - box.lo[a]) * (double(box.hi[b]) - box.lo[b]);
    if (face > 0) return 0;
    const std::size_t both = child + sibling - n;
    const bool copies_most = 2 * both >= n;
    const bool keeps_nearly_all = sibling > 0 && 10 * child >= 9 * n;
    return copies_most || keeps_nearly_all ? 1 : 0;
  }
  static constexpr int kMaxUnproductiveSplits = 4;

  // Builds the subtree of `node` into a fragment of its own, for splice().
  BuiltNodes build_fragment(NodeInput&& node) {
    BuiltNodes part;
    // This builder may be waiting inside a subtree of its own output: back to it after.
    BuiltNodes* const outer = std::exchange(output_, &part);
    try {
      build_node(std::move(node));
    } catch (...) {
      output_ = outer;
      throw;
    }
    output_ = outer;
    return part;
  }

  // Puts a subtree built apart after the nodes made so far: it is the right subtree of `parent`.
  void splice(std::uint32_t parent, std::unique_ptr<BuiltNodes> part) {
    output_->spliced_nodes += part->total_nodes();
    output_->spliced_primitives += part->total_primitives();
    output_->spliced.push_back({static_cast<std::uint32_t>(output_->nodes.size()),
                                static_cast<std::uint32_t>(output_->primitives.size()), parent, std::move(part)});
  }


  // Appends a node's events of one axis to its children's lists (at
  // left[left_size] and right[right_size], sizes counted on), each merged
  // with the sorted events of its clipped triangles, so both stay sorted.
  // Without a branch on the side: the sides of an axis's events alternate at
  // random, and a branch on them mispredicts about half the time. Each event
  // is written to both lists and counted in the one its side names.
  void split_events(std::span<const Event> events, const std::vector<Event>& clipped_left,
                    const std::vector<Event>& clipped_right, Event* left, std::size_t& left_size, Event* right,
                    std::size_t& right_size) const {
    const Event* next_left = clipped_left.data();
    const Event* const left_end = next_left + clipped_left.size();
    const Event* next_right = clipped_right.data();
    const Event* const right_end = next_right + clipped_right.size();
    std::size_t l = left_size, r = right_size;
    for (const Event& e : events) {
      for (; next_left != left_end && event_less(*next_left, e); ++next_left) left[l++] = *next_left;
      for (; next_right != right_end && event_less(*next_right, e); ++next_right) right[r++] = *next_right;
      const std::uint8_t side = side_[e.triangle()];
      left[l] = e;
      l += side == kLeftOnly;
      right[r] = e;
      r += side == kRightOnly;
    }
    left_size = std::copy(next_left, left_end, left + l) - left;
    right_size = std::copy(next_right, right_end, right + r) - right;
  }

  std::span<const Triangle> triangles_;
  KdBuildOptions options_;
  int max_depth_;
  double root_area_;  // the SAH cost's denominator
  TaskPool& pool_;
  const Builders& builders_;  // one per pool thread
  unsigned thread_;           // the pool thread this builder runs on
  BuiltNodes* output_ = nullptr;  // the tree or fragment being built
  std::vector<std::uint8_t> side_;
  AxisEvents new_left_, new_right_;  // scratch: events of the triangles one node clips
  EventList sort_buffer_;
  SpareVectors<EventList> spare_events_;
  SpareVectors<std::vector<std::uint32_t>> spare_ids_;
};

BuiltNodes build_nodes(std::span<const Triangle> triangles, const KdBuildOptions& options, int max_depth,
                       const Bounds& root_box, TaskPool& pool) {
  KdTreeBuilder::Builders builders;
  for (unsigned thread = 0; thread < pool.threads(); ++thread) {
    builders.push_back(std::make_unique<KdTreeBuilder>(triangles, options, max_depth, surface_area(root_box),
                                                       pool, builders, thread));
  }
  return builders[0]->build_tree(root_box);
}

}  // namespace nodetrace::tracer::kd_build
