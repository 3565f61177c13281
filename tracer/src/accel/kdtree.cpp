#include "nodetrace/tracer/accel/kdtree.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <future>
#include <memory>
#include <limits>
#include <utility>

namespace nodetrace::tracer {

namespace {

// Event order at one position: ends before planars before starts, so a sweep
// sees a plane with the triangles ending on it already counted left.
enum EventType : std::uint8_t { kEnd = 0, kPlanar = 1, kStart = 2 };

struct Event {
  float position;
  std::uint32_t triangle;
  std::uint8_t axis;
  std::uint8_t type;
};

// Total order (axis, position, type, triangle): events of one axis are
// contiguous, and ties are broken by triangle so sorting is deterministic.
bool event_less(const Event& a, const Event& b) {
  if (a.axis != b.axis) return a.axis < b.axis;
  if (a.position != b.position) return a.position < b.position;
  if (a.type != b.type) return a.type < b.type;
  return a.triangle < b.triangle;
}

enum Side : std::uint8_t { kBoth = 0, kLeftOnly = 1, kRightOnly = 2 };

double surface_area(const Bounds& box) {
  const double dx = double(box.hi.x) - box.lo.x, dy = double(box.hi.y) - box.lo.y,
               dz = double(box.hi.z) - box.lo.z;
  return 2.0 * (dx * dy + dy * dz + dz * dx);
}

void add_events(std::vector<Event>& events, std::uint32_t triangle, const Bounds& box) {
  for (std::uint8_t axis = 0; axis < 3; ++axis) {
    if (box.lo[axis] == box.hi[axis]) {
      events.push_back({box.lo[axis], triangle, axis, kPlanar});
    } else {
      events.push_back({box.lo[axis], triangle, axis, kStart});
      events.push_back({box.hi[axis], triangle, axis, kEnd});
    }
  }
}

struct SplitChoice {
  double cost = std::numeric_limits<double>::infinity();
  float position = 0;
  int axis = -1;
  bool planar_left = true;
};

}  // namespace

int default_max_depth(std::size_t triangle_count) {
  if (triangle_count < 2) return 8;
  return 8 + static_cast<int>(std::lround(1.3 * std::log2(static_cast<double>(triangle_count))));
}

Bounds clip_triangle_to_box(const Triangle& triangle, const Bounds& box) {
  // Up to 3 + 6 vertices after clipping a triangle by six planes.
  std::array<Vec3, 10> polygon{triangle.v0, triangle.v1, triangle.v2};
  std::array<Vec3, 10> clipped{};
  std::size_t count = 3;
  for (int axis = 0; axis < 3 && count > 0; ++axis) {
    for (int face = 0; face < 2 && count > 0; ++face) {
      const float plane = face == 0 ? box.lo[axis] : box.hi[axis];
      // Inside: >= plane for the low face, <= plane for the high face.
      auto inside = [&](const Vec3& p) { return face == 0 ? p[axis] >= plane : p[axis] <= plane; };
      std::size_t out = 0;
      for (std::size_t i = 0; i < count; ++i) {
        const Vec3& a = polygon[i];
        const Vec3& b = polygon[(i + 1) % count];
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

class KdTreeBuilder {
 public:
  KdTreeBuilder(std::span<const Triangle> triangles, const KdBuildOptions& options, KdTree& tree)
      : triangles_(triangles), options_(options), tree_(tree), side_(triangles.size(), kBoth) {}

  void run() {
    Bounds root_box;
    for (const auto& t : triangles_) {
      root_box.extend(t.v0);
      root_box.extend(t.v1);
      root_box.extend(t.v2);
    }
    tree_.bounds_ = root_box;
    max_depth_ = options_.max_depth > 0 ? options_.max_depth : default_max_depth(triangles_.size());
    max_depth_ = std::min(max_depth_, kMaxLevelLimit);  // traversal stacks are sized for it
    root_area_ = root_box.empty() ? 0.0 : surface_area(root_box);

    std::vector<Event> events;
    std::vector<std::uint32_t> ids;
    events.reserve(triangles_.size() * 6);
    ids.reserve(triangles_.size());
    for (std::uint32_t i = 0; i < triangles_.size(); ++i) {
      const Triangle& t = triangles_[i];
      Bounds box;
      box.extend(t.v0);
      box.extend(t.v1);
      box.extend(t.v2);
      add_events(events, i, box);
      ids.push_back(i);
    }
    std::sort(events.begin(), events.end(), event_less);
    build_node(std::move(events), std::move(ids), root_box, 0);
  }

  double sah_cost() const { return sah_cost_; }
  int max_depth() const { return max_depth_; }

 private:
  SplitChoice find_split(const std::vector<Event>& events, std::size_t n, const Bounds& box) const {
    SplitChoice best;
    const double area = surface_area(box);
    if (!(area > 0)) return best;
    const double kt = options_.traversal_cost, ki = options_.intersection_cost;
    const double bonus = 1.0 - options_.empty_bonus;
    std::size_t left = 0, right = n;
    int current_axis = -1;
    std::size_t i = 0;
    while (i < events.size()) {
      const int axis = events[i].axis;
      const float position = events[i].position;
      if (axis != current_axis) {
        current_axis = axis;
        left = 0;
        right = n;
      }
      std::size_t ending = 0, planar = 0, starting = 0;
      while (i < events.size() && events[i].axis == axis && events[i].position == position &&
             events[i].type == kEnd) {
        ++ending, ++i;
      }
      while (i < events.size() && events[i].axis == axis && events[i].position == position &&
             events[i].type == kPlanar) {
        ++planar, ++i;
      }
      while (i < events.size() && events[i].axis == axis && events[i].position == position &&
             events[i].type == kStart) {
        ++starting, ++i;
      }
      right -= planar + ending;
      // Planes on the box faces cut nothing off; both children need volume.
      if (position > box.lo[axis] && position < box.hi[axis]) {
        Bounds lbox = box, rbox = box;
        lbox.hi[axis] = position;
        rbox.lo[axis] = position;
        const double pl = surface_area(lbox) / area, pr = surface_area(rbox) / area;
        auto cost = [&](std::size_t nl, std::size_t nr) {
          const double c = kt + ki * (pl * double(nl) + pr * double(nr));
          return (nl == 0 || nr == 0) ? c * bonus : c;
        };
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

  std::uint32_t make_leaf(std::uint32_t index, const std::vector<std::uint32_t>& ids,
                          const Bounds& box) {
    KdNode& node = tree_.nodes_[index];
    node.axis = KdNode::kLeafAxis;
    node.first = static_cast<std::uint32_t>(tree_.primitives_.size());
    node.count = static_cast<std::uint32_t>(ids.size());
    tree_.primitives_.insert(tree_.primitives_.end(), ids.begin(), ids.end());
    if (root_area_ > 0) {
      sah_cost_ += options_.intersection_cost * double(ids.size()) * surface_area(box) / root_area_;
    }
    return index;
  }

  std::uint32_t build_node(std::vector<Event> events, std::vector<std::uint32_t> ids,
                           const Bounds& box, int level, int unproductive = 0) {
    const auto index = static_cast<std::uint32_t>(tree_.nodes_.size());
    tree_.nodes_.emplace_back();
    tree_.nodes_[index].level = static_cast<std::uint16_t>(level);
    const std::size_t n = ids.size();
    if (n == 0 || n <= options_.leaf_size || level >= max_depth_ || unproductive >= kMaxUnproductiveSplits) {
      return make_leaf(index, ids, box);
    }
    const SplitChoice split = find_split(events, n, box);
    if (split.axis < 0 || split.cost >= options_.intersection_cost * double(n)) {
      return make_leaf(index, ids, box);
    }

    // Classify: which triangles lie only left, only right, or on both sides.
    for (auto id : ids) side_[id] = kBoth;
    for (const Event& e : events) {
      if (e.axis != split.axis) continue;
      if (e.type == kEnd && e.position <= split.position) {
        side_[e.triangle] = kLeftOnly;
      } else if (e.type == kStart && e.position >= split.position) {
        side_[e.triangle] = kRightOnly;
      } else if (e.type == kPlanar) {
        if (e.position < split.position || (e.position == split.position && split.planar_left)) {
          side_[e.triangle] = kLeftOnly;
        } else {
          side_[e.triangle] = kRightOnly;
        }
      }
    }

    Bounds left_box = box, right_box = box;
    left_box.hi[split.axis] = split.position;
    right_box.lo[split.axis] = split.position;

    std::vector<Event> left_events, right_events, new_left, new_right;
    std::vector<std::uint32_t> left_ids, right_ids;
    {
      std::size_t left_count = 0, right_count = 0;
      for (const Event& e : events) {
        left_count += side_[e.triangle] == kLeftOnly;
        right_count += side_[e.triangle] == kRightOnly;
      }
      left_events.reserve(left_count);
      right_events.reserve(right_count);
    }
    for (const Event& e : events) {
      if (side_[e.triangle] == kLeftOnly) {
        left_events.push_back(e);
      } else if (side_[e.triangle] == kRightOnly) {
        right_events.push_back(e);
      }
    }
    for (auto id : ids) {
      if (side_[id] == kLeftOnly) {
        left_ids.push_back(id);
      } else if (side_[id] == kRightOnly) {
        right_ids.push_back(id);
      } else {
        // Straddling: clip to each child (perfect splits), new events per side.
        const Bounds l = clip_triangle_to_box(triangles_[id], left_box);
        if (!l.empty()) {
          add_events(new_left, id, l);
          left_ids.push_back(id);
        }
        const Bounds r = clip_triangle_to_box(triangles_[id], right_box);
        if (!r.empty()) {
          add_events(new_right, id, r);
          right_ids.push_back(id);
        }
      }
    }
    const int left_unproductive = unproductive + unproductive_for(box, split, n, left_ids.size(), right_ids.size());
    const int right_unproductive = unproductive + unproductive_for(box, split, n, right_ids.size(), left_ids.size());
    // Release the parent's lists before going down.
    std::vector<Event>().swap(events);
    std::vector<std::uint32_t>().swap(ids);
    merge_into(left_events, new_left);
    merge_into(right_events, new_right);
    // Triangle ids stay ascending in every list (filtered in order), so
    // leaves list them in order.

    if (root_area_ > 0) sah_cost_ += options_.traversal_cost * surface_area(box) / root_area_;
    {
      KdNode& node = tree_.nodes_[index];
      node.axis = static_cast<std::uint8_t>(split.axis);
      node.split = split.position;
    }
    new_left.clear();
    new_right.clear();
    std::uint32_t left, right;
    if (level < kParallelLevels) {
      // The right subtree is built by its own builder on another thread while
      // this one builds the left; it is then appended in pre-order. The split
      // into tasks is fixed, so the tree does not depend on the thread count.
      auto fragment = std::async(std::launch::async, [this, events = std::move(right_events),
                                                      ids = std::move(right_ids), right_box,
                                                      level, right_unproductive]() mutable {
        auto part = std::make_unique<KdTree>();
        KdTreeBuilder builder(triangles_, options_, *part);
        builder.max_depth_ = max_depth_;
        builder.root_area_ = root_area_;
        builder.build_node(std::move(events), std::move(ids), right_box, level + 1, right_unproductive);
        return std::make_pair(std::move(part), builder.sah_cost_);
      });
      left = build_node(std::move(left_events), std::move(left_ids), left_box, level + 1, left_unproductive);
      auto [part, cost] = fragment.get();
      right = append(*part);
      sah_cost_ += cost;
    } else {
      left = build_node(std::move(left_events), std::move(left_ids), left_box, level + 1, left_unproductive);
      right = build_node(std::move(right_events), std::move(right_ids), right_box, level + 1, right_unproductive);
    }
    tree_.nodes_[index].left = left;
    tree_.nodes_[index].right = right;
    return index;
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

  // Appends a subtree built apart; returns the index of its root.
  std::uint32_t append(const KdTree& part) {
    const auto node_offset = static_cast<std::uint32_t>(tree_.nodes_.size());
    const auto primitive_offset = static_cast<std::uint32_t>(tree_.primitives_.size());
    for (KdNode node : part.nodes_) {
      if (node.is_leaf()) {
        node.first += primitive_offset;
      } else {
        node.left += node_offset;
        node.right += node_offset;
      }
      tree_.nodes_.push_back(node);
    }
    tree_.primitives_.insert(tree_.primitives_.end(), part.primitives_.begin(), part.primitives_.end());
    return node_offset;
  }

  // Levels whose right subtrees are built on their own threads (up to 7 tasks).
  static constexpr int kParallelLevels = 3;

  static void merge_into(std::vector<Event>& sorted, std::vector<Event>& extra) {
    if (extra.empty()) return;
    std::sort(extra.begin(), extra.end(), event_less);
    std::vector<Event> merged(sorted.size() + extra.size());
    std::merge(sorted.begin(), sorted.end(), extra.begin(), extra.end(), merged.begin(), event_less);
    sorted.swap(merged);
  }

  std::span<const Triangle> triangles_;
  KdBuildOptions options_;
  KdTree& tree_;
  std::vector<std::uint8_t> side_;
  int max_depth_ = 0;
  double root_area_ = 0;
  double sah_cost_ = 0;
};

KdTree KdTree::build(std::span<const Triangle> triangles, const KdBuildOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  KdTree tree;
  KdTreeBuilder builder(triangles, options, tree);
  builder.run();

  tree.stats_.depth_limit = builder.max_depth();
  tree.stats_.sah_cost = builder.sah_cost();
  tree.compute_stats();
  tree.stats_.build_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
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
  KdTreeStats& s = stats_;
  s.nodes = nodes_.size();
  s.interior = s.leaves = s.empty_leaves = s.primitive_references = 0;
  s.nodes_per_level.clear();
  s.depth = 0;
  for (const KdNode& node : nodes_) {
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
  if (s.leaves > 0) s.mean_leaf_size = double(s.primitive_references) / double(s.leaves);
  if (s.leaves > s.empty_leaves) {
    s.mean_nonempty_leaf_size = double(s.primitive_references) / double(s.leaves - s.empty_leaves);
  }
}

}  // namespace nodetrace::tracer
