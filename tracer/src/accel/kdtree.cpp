#include "nodetrace/tracer/accel/kdtree.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <chrono>
#include <cmath>
#include <ctime>
#include <future>
#include <limits>
#include <memory>
#include <stdexcept>
#include <thread>
#include <utility>

namespace nodetrace::tracer {

namespace {

// Event order at one position: ends before planars before starts, so a sweep
// sees a plane with the triangles ending on it already counted left.
enum EventType : std::uint32_t { kEnd = 0, kPlanar = 1, kStart = 2 };

// Triangle indices take the low 30 bits of an event, its type the top two.
constexpr unsigned kTriangleBits = 30;
constexpr std::uint32_t kTriangleMask = (std::uint32_t{1} << kTriangleBits) - 1;

// Where a triangle's (clipped) extent starts, ends, or lies flat on one axis.
struct Event {
  float position;
  std::uint32_t type_and_triangle;
  std::uint32_t triangle() const { return type_and_triangle & kTriangleMask; }
  std::uint32_t type() const { return type_and_triangle >> kTriangleBits; }
};

// Total order (position, type, triangle) within an axis; ties are broken by
// triangle, so sorting is deterministic.
inline bool event_less(const Event& a, const Event& b) {
  return a.position < b.position || (a.position == b.position && a.type_and_triangle < b.type_and_triangle);
}

// A node's events: those of axis a, sorted, are [begin[a], begin[a + 1]).
struct NodeEvents {
  std::vector<Event> events;
  std::array<std::size_t, 4> begin{};
  std::span<const Event> axis(int a) const { return {events.data() + begin[a], events.data() + begin[a + 1]}; }
};

// Events of triangles clipped in one node, one list per axis.
using AxisEvents = std::array<std::vector<Event>, 3>;

enum Side : std::uint8_t { kBoth = 0, kLeftOnly = 1, kRightOnly = 2 };

double surface_area(const Bounds& box) {
  const double dx = double(box.hi.x) - box.lo.x, dy = double(box.hi.y) - box.lo.y,
               dz = double(box.hi.z) - box.lo.z;
  return 2.0 * (dx * dy + dy * dz + dz * dx);
}

void add_events(AxisEvents& events, std::uint32_t triangle, const Bounds& box) {
  for (int axis = 0; axis < 3; ++axis) {
    auto& list = events[axis];
    if (box.lo[axis] == box.hi[axis]) {
      list.push_back({box.lo[axis], kPlanar << kTriangleBits | triangle});
    } else {
      list.push_back({box.lo[axis], kStart << kTriangleBits | triangle});
      list.push_back({box.hi[axis], kEnd << kTriangleBits | triangle});
    }
  }
}

// The event order as one integer: the position's bits made to sort as the
// float does (-0 and +0 as one), then type and triangle.
std::uint64_t sort_key(const Event& e) {
  const float position = e.position == 0.0f ? 0.0f : e.position;
  std::uint32_t bits = std::bit_cast<std::uint32_t>(position);
  bits = (bits & 0x80000000u) != 0 ? ~bits : bits | 0x80000000u;
  return std::uint64_t{bits} << 32 | e.type_and_triangle;
}

// LSD radix sort on sort_key, a byte per pass; passes where every event has
// the same byte are skipped.
void radix_sort(std::vector<Event>& events) {
  constexpr int kPasses = 8;
  std::vector<std::array<std::uint32_t, 256>> counts(kPasses, std::array<std::uint32_t, 256>{});
  for (const Event& e : events) {
    const std::uint64_t key = sort_key(e);
    for (int pass = 0; pass < kPasses; ++pass) ++counts[pass][(key >> (8 * pass)) & 0xff];
  }
  std::vector<Event> buffer(events.size());
  for (int pass = 0; pass < kPasses; ++pass) {
    auto& count = counts[pass];
    if (std::find(count.begin(), count.end(), events.size()) != count.end()) continue;
    std::uint32_t offset = 0;
    for (auto& c : count) offset += std::exchange(c, offset);
    for (const Event& e : events) buffer[count[(sort_key(e) >> (8 * pass)) & 0xff]++] = e;
    events.swap(buffer);
  }
}

void sort_events(std::vector<Event>& events) {
  // Radix sorting pays off for long lists only.
  if (events.size() >= 4096) {
    radix_sort(events);
  } else {
    std::sort(events.begin(), events.end(), event_less);
  }
}

struct SplitChoice {
  double cost = std::numeric_limits<double>::infinity();
  float position = 0;
  int axis = -1;
  bool planar_left = true;
};

// Lists a builder has done with, for its next nodes: the build allocates
// (and the system zeroes) far less. Depth-first, few are spare at a time;
// long lists, from the few nodes near the root, are freed.
template <typename T>
class SpareVectors {
 public:
  static constexpr std::size_t kLongest = std::size_t{1} << 15;
  std::vector<T> take() {
    if (spare_.empty()) return {};
    std::vector<T> list = std::move(spare_.back());
    spare_.pop_back();
    return list;
  }
  void give(std::vector<T>&& list) {
    if (list.capacity() > kLongest) return;
    list.clear();
    spare_.push_back(std::move(list));
  }

 private:
  std::vector<std::vector<T>> spare_;
};

// Threads a build may still start, shared by the builders of one tree.
class ThreadSlots {
 public:
  explicit ThreadSlots(unsigned threads) : free_(static_cast<int>(threads) - 1) {}
  bool try_take() {
    int free = free_.load(std::memory_order_relaxed);
    while (free > 0) {
      if (free_.compare_exchange_weak(free, free - 1, std::memory_order_acquire)) return true;
    }
    return false;
  }
  void give_back() { free_.fetch_add(1, std::memory_order_release); }
  // Taken back after a wait whatever is free: briefly one thread too many.
  void take() { free_.fetch_sub(1, std::memory_order_acquire); }

 private:
  std::atomic<int> free_;
};

unsigned build_threads(unsigned requested) {
  if (requested > 0) return requested;
  return std::max(1u, std::thread::hardware_concurrency());
}

}  // namespace

int default_max_depth(std::size_t triangle_count) {
  if (triangle_count < 2) return 8;
  return 8 + static_cast<int>(std::lround(1.3 * std::log2(static_cast<double>(triangle_count))));
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

class KdTreeBuilder {
 public:
  KdTreeBuilder(std::span<const Triangle> triangles, const KdBuildOptions& options, KdTree& tree,
                ThreadSlots& slots)
      : triangles_(triangles), options_(options), tree_(tree), slots_(slots), side_(triangles.size(), kBoth) {}

  void run() {
    if (triangles_.size() > kTriangleMask) {
      throw std::length_error("kd-tree build: more than 2^30 triangles");
    }
    Bounds root_box;
    for (const auto& t : triangles_) {
      root_box.extend(t.v0);
      root_box.extend(t.v1);
      root_box.extend(t.v2);
    }
    tree_.bounds_ = root_box;
    max_depth_ = options_.max_depth > 0 ? options_.max_depth : default_max_depth(triangles_.size());
    max_depth_ = std::min(max_depth_, kMaxLevelLimit);  // traversal stacks are sized for it

    AxisEvents events;
    std::vector<std::uint32_t> ids;
    for (auto& list : events) list.reserve(triangles_.size() * 2);
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
    // The three axes sort apart; the first two on threads of their own when free.
    std::array<std::future<void>, 2> sorts;
    std::array<bool, 2> on_thread{};
    for (int axis = 0; axis < 2; ++axis) {
      on_thread[axis] = slots_.try_take();
      if (on_thread[axis]) sorts[axis] = std::async(std::launch::async, sort_events, std::ref(events[axis]));
    }
    sort_events(events[2]);
    for (int axis = 0; axis < 2; ++axis) {
      if (on_thread[axis]) {
        sorts[axis].get();
        slots_.give_back();
      } else {
        sort_events(events[axis]);
      }
    }
    NodeEvents root;
    root.events.reserve(events[0].size() + events[1].size() + events[2].size());
    for (int axis = 0; axis < 3; ++axis) {
      root.begin[axis] = root.events.size();
      root.events.insert(root.events.end(), events[axis].begin(), events[axis].end());
      std::vector<Event>().swap(events[axis]);
    }
    root.begin[3] = root.events.size();
    build_node(std::move(root), std::move(ids), root_box, 0);
  }

  int max_depth() const { return max_depth_; }

 private:
  SplitChoice find_split(const NodeEvents& events, std::size_t n, const Bounds& box) const {
    SplitChoice best;
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
    for (int axis = 0; axis < 3; ++axis) {
      const std::span<const Event> list = events.axis(axis);
      const Event* e = list.data();
      const Event* const last = e + list.size();
      std::size_t left = 0, right = n;
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
    }
    return best;
  }

  std::uint32_t make_leaf(std::uint32_t index, NodeEvents events, std::vector<std::uint32_t> ids) {
    KdNode& node = tree_.nodes_[index];
    node.axis = KdNode::kLeafAxis;
    node.first = static_cast<std::uint32_t>(tree_.primitives_.size());
    node.count = static_cast<std::uint32_t>(ids.size());
    tree_.primitives_.insert(tree_.primitives_.end(), ids.begin(), ids.end());
    spare_events_.give(std::move(events.events));
    spare_ids_.give(std::move(ids));
    return index;
  }

  std::uint32_t build_node(NodeEvents events, std::vector<std::uint32_t> ids, const Bounds& box, int level,
                           int unproductive = 0) {
    const auto index = static_cast<std::uint32_t>(tree_.nodes_.size());
    tree_.nodes_.emplace_back();
    tree_.nodes_[index].level = static_cast<std::uint16_t>(level);
    const std::size_t n = ids.size();
    if (n == 0 || n <= options_.leaf_size || level >= max_depth_ || unproductive >= kMaxUnproductiveSplits) {
      return make_leaf(index, std::move(events), std::move(ids));
    }
    const SplitChoice split = find_split(events, n, box);
    if (split.axis < 0 || split.cost >= options_.intersection_cost * double(n)) {
      return make_leaf(index, std::move(events), std::move(ids));
    }

    // Classify: which triangles lie only left, only right, or on both sides.
    for (auto id : ids) side_[id] = kBoth;
    for (const Event& e : events.axis(split.axis)) {
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

    Bounds left_box = box, right_box = box;
    left_box.hi[split.axis] = split.position;
    right_box.lo[split.axis] = split.position;

    std::vector<std::uint32_t> left_ids = spare_ids_.take(), right_ids = spare_ids_.take();
    for (auto& list : new_left_) list.clear();
    for (auto& list : new_right_) list.clear();
    for (auto id : ids) {
      if (side_[id] == kLeftOnly) {
        left_ids.push_back(id);
      } else if (side_[id] == kRightOnly) {
        right_ids.push_back(id);
      } else {
        // Straddling: clip to each child (perfect splits), new events per side.
        const Bounds l = clip_triangle_to_box(triangles_[id], left_box);
        if (!l.empty()) {
          add_events(new_left_, id, l);
          left_ids.push_back(id);
        }
        const Bounds r = clip_triangle_to_box(triangles_[id], right_box);
        if (!r.empty()) {
          add_events(new_right_, id, r);
          right_ids.push_back(id);
        }
      }
    }
    NodeEvents left_events{spare_events_.take()}, right_events{spare_events_.take()};
    // At most two events per triangle and axis.
    left_events.events.reserve(6 * left_ids.size());
    right_events.events.reserve(6 * right_ids.size());
    for (int axis = 0; axis < 3; ++axis) {
      sort_events(new_left_[axis]);
      sort_events(new_right_[axis]);
      left_events.begin[axis] = left_events.events.size();
      right_events.begin[axis] = right_events.events.size();
      split_events(events.axis(axis), new_left_[axis], new_right_[axis], left_events.events, right_events.events);
    }
    left_events.begin[3] = left_events.events.size();
    right_events.begin[3] = right_events.events.size();
    spare_events_.give(std::move(events.events));  // the parent's list, for the children's children
    // Triangle ids stay ascending in every list (filtered in order), so
    // leaves list them in order.
    const int left_unproductive = unproductive + unproductive_for(box, split, n, left_ids.size(), right_ids.size());
    const int right_unproductive = unproductive + unproductive_for(box, split, n, right_ids.size(), left_ids.size());
    spare_ids_.give(std::move(ids));
    {
      KdNode& node = tree_.nodes_[index];
      node.axis = static_cast<std::uint8_t>(split.axis);
      node.split = split.position;
    }
    std::uint32_t left, right;
    const bool right_smaller = right_ids.size() <= left_ids.size();
    if (std::min(left_ids.size(), right_ids.size()) >= kMinTrianglesPerThread && slots_.try_take()) {
      // The smaller child is built by a builder of its own on another thread
      // while this one builds the larger (it is the likelier to find another
      // split worth a thread), then appended in pre-order: the tree does not
      // depend on the threads.
      auto on_thread = [this](NodeEvents&& events, std::vector<std::uint32_t>&& ids, const Bounds& box, int level,
                              int unproductive) {
        return std::async(std::launch::async, [this, events = std::move(events), ids = std::move(ids), box, level,
                                               unproductive]() mutable {
          auto part = build_fragment(std::move(events), std::move(ids), box, level, unproductive);
          slots_.give_back();
          return part;
        });
      };
      // While this thread waits, the other builders may start one in its place.
      auto wait_for = [this](std::future<std::unique_ptr<KdTree>>& fragment) {
        slots_.give_back();
        std::unique_ptr<KdTree> part = fragment.get();
        slots_.take();
        return part;
      };
      if (right_smaller) {
        auto fragment = on_thread(std::move(right_events), std::move(right_ids), right_box, level + 1,
                                  right_unproductive);
        left = build_node(std::move(left_events), std::move(left_ids), left_box, level + 1, left_unproductive);
        right = append(*wait_for(fragment));
      } else {
        auto fragment = on_thread(std::move(left_events), std::move(left_ids), left_box, level + 1,
                                  left_unproductive);
        const std::unique_ptr<KdTree> right_part = build_fragment(
            std::move(right_events), std::move(right_ids), right_box, level + 1, right_unproductive);
        left = append(*wait_for(fragment));
        right = append(*right_part);
      }
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

  // A subtree built apart by a builder of its own, for append().
  std::unique_ptr<KdTree> build_fragment(NodeEvents events, std::vector<std::uint32_t> ids, const Bounds& box,
                                         int level, int unproductive) const {
    auto part = std::make_unique<KdTree>();
    KdTreeBuilder builder(triangles_, options_, *part, slots_);
    builder.max_depth_ = max_depth_;
    builder.build_node(std::move(events), std::move(ids), box, level, unproductive);
    return part;
  }

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

  // A child of fewer triangles is not worth a thread.
  static constexpr std::size_t kMinTrianglesPerThread = 1024;

  // Appends a node's events of one axis to its children's lists, each merged
  // with the sorted events of its clipped triangles, so both stay sorted.
  void split_events(std::span<const Event> events, const std::vector<Event>& clipped_left,
                    const std::vector<Event>& clipped_right, std::vector<Event>& left,
                    std::vector<Event>& right) const {
    const Event* next_left = clipped_left.data();
    const Event* const left_end = next_left + clipped_left.size();
    const Event* next_right = clipped_right.data();
    const Event* const right_end = next_right + clipped_right.size();
    for (const Event& e : events) {
      const std::uint8_t side = side_[e.triangle()];
      if (side == kLeftOnly) {
        for (; next_left != left_end && event_less(*next_left, e); ++next_left) left.push_back(*next_left);
        left.push_back(e);
      } else if (side == kRightOnly) {
        for (; next_right != right_end && event_less(*next_right, e); ++next_right) right.push_back(*next_right);
        right.push_back(e);
      }
    }
    left.insert(left.end(), next_left, left_end);
    right.insert(right.end(), next_right, right_end);
  }

  std::span<const Triangle> triangles_;
  KdBuildOptions options_;
  KdTree& tree_;
  ThreadSlots& slots_;
  std::vector<std::uint8_t> side_;
  AxisEvents new_left_, new_right_;  // scratch: events of the triangles one node clips
  SpareVectors<Event> spare_events_;
  SpareVectors<std::uint32_t> spare_ids_;
  int max_depth_ = 0;
};

namespace {

// The expected cost of a ray through the root box: each interior node's
// traversal and each leaf's tests, weighted by the node box's area, summed
// in pre-order.
double sah_cost(const KdTree& tree, const KdBuildOptions& options) {
  const auto& nodes = tree.nodes();
  if (nodes.empty() || tree.bounds().empty()) return 0;
  const double root_area = surface_area(tree.bounds());
  if (!(root_area > 0)) return 0;
  double cost = 0;
  std::vector<std::pair<std::uint32_t, Bounds>> stack{{0, tree.bounds()}};
  while (!stack.empty()) {
    const auto [index, box] = stack.back();
    stack.pop_back();
    const KdNode& node = nodes[index];
    if (node.is_leaf()) {
      cost += options.intersection_cost * double(node.count) * surface_area(box) / root_area;
      continue;
    }
    cost += options.traversal_cost * surface_area(box) / root_area;
    Bounds left = box, right = box;
    left.hi[node.axis] = node.split;
    right.lo[node.axis] = node.split;
    stack.push_back({node.right, right});
    stack.push_back({node.left, left});
  }
  return cost;
}

}  // namespace

KdTree KdTree::build(std::span<const Triangle> triangles, const KdBuildOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  const std::clock_t cpu_start = std::clock();
  KdTree tree;
  ThreadSlots slots(build_threads(options.threads));
  KdTreeBuilder builder(triangles, options, tree, slots);
  builder.run();

  tree.stats_.depth_limit = builder.max_depth();
  tree.stats_.sah_cost = sah_cost(tree, options);
  tree.compute_stats();
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
