// Binned SAH build of the binary BVH (Wald 2007, "On fast construction of
// SAH-based bounding volume hierarchies"), then the collapse to wide nodes
// and the quantization of compressed ones.
#include <algorithm>
#include <chrono>
#include <ctime>
#include <cmath>
#include <future>
#include <limits>
#include <memory>
#include <stdexcept>

#include "nodetrace/base/portable_math.hpp"
#include "accel/box_test.hpp"
#include "nodetrace/tracer/accel/bvh.hpp"

namespace nodetrace::tracer {

// The same results on every machine (portable_math.hpp).
namespace math = base::portable_math;

namespace {

Bounds merged(const Bounds& a, const Bounds& b) {
  Bounds m = a;
  if (!b.empty()) {
    m.extend(b.lo);
    m.extend(b.hi);
  }
  return m;
}

struct BinaryNode {
  Bounds box;
  std::unique_ptr<BinaryNode> left, right;
  std::uint32_t first = 0, count = 0;  // leaf: ids[first, first + count)
  bool is_leaf() const { return !left; }
};

// Subtrees of at least this many triangles above this level are built on
// a thread of their own (the top levels: two cores and some slack).
constexpr std::uint32_t kParallelLevels = 3;
constexpr std::uint32_t kParallelMinTriangles = 4096;

}  // namespace

class BvhBuilder {
 public:
  BvhBuilder(std::span<const Triangle> triangles, const BvhBuildOptions& options) : options_(options) {
    const std::size_t n = triangles.size();
    boxes_.resize(n);
    centroids_.resize(n);
    ids_.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      Bounds b;
      b.extend(triangles[i].v0);
      b.extend(triangles[i].v1);
      b.extend(triangles[i].v2);
      boxes_[i] = b;
      centroids_[i] = (b.lo + b.hi) * 0.5f;
      ids_[i] = static_cast<std::uint32_t>(i);
    }
  }

  std::unique_ptr<BinaryNode> build_binary() {
    if (ids_.empty()) return nullptr;
    return build(0, static_cast<std::uint32_t>(ids_.size()), 0);
  }

  std::vector<std::uint32_t> take_ids() { return std::move(ids_); }

 private:
  std::unique_ptr<BinaryNode> build(std::uint32_t begin, std::uint32_t end, std::uint32_t level) {
    auto node = std::make_unique<BinaryNode>();
    Bounds centroid_box;
    for (std::uint32_t i = begin; i < end; ++i) {
      node->box = merged(node->box, boxes_[ids_[i]]);
      centroid_box.extend(centroids_[ids_[i]]);
    }
    const std::uint32_t count = end - begin;
    const std::uint32_t middle = split(begin, end, level, node->box, centroid_box);
    if (middle == begin) {
      node->first = begin;
      node->count = count;
      return node;
    }
    if (level < kParallelLevels && count >= kParallelMinTriangles) {
      auto left = std::async(std::launch::async, [&, begin, middle, level] { return build(begin, middle, level + 1); });
      node->right = build(middle, end, level + 1);
      node->left = left.get();
    } else {
      node->left = build(begin, middle, level + 1);
      node->right = build(middle, end, level + 1);
    }
    return node;
  }

  // Partitions ids_[begin, end) and returns where the right part starts, or
  // `begin` for a leaf.
  std::uint32_t split(std::uint32_t begin, std::uint32_t end, std::uint32_t level, const Bounds& box,
                      const Bounds& centroid_box) {
    const std::uint32_t count = end - begin;
    if (count <= 1) return begin;
    int widest = 0;
    for (int a = 1; a < 3; ++a) {
      if (centroid_box.hi[a] - centroid_box.lo[a] > centroid_box.hi[widest] - centroid_box.lo[widest]) widest = a;
    }
    const auto median = [&] {
      const std::uint32_t middle = begin + count / 2;
      std::nth_element(ids_.begin() + begin, ids_.begin() + middle, ids_.begin() + end,
                       [&](std::uint32_t a, std::uint32_t b) {
                         const float ca = centroids_[a][widest], cb = centroids_[b][widest];
                         return ca < cb || (ca == cb && a < b);
                       });
      return middle;
    };
    if (level >= kBvhMedianFromLevel) return count <= options_.max_leaf_size ? begin : median();

    const std::uint32_t bins = std::clamp<std::uint32_t>(options_.bins, 2, 256);
    double best_cost = std::numeric_limits<double>::infinity();
    int best_axis = -1;
    std::uint32_t best_plane = 0;
    std::vector<Bounds> bin_box(bins), right_box(bins);
    std::vector<std::uint32_t> bin_count(bins), right_count(bins);
    for (int axis = 0; axis < 3; ++axis) {
      const float lo = centroid_box.lo[axis], extent = centroid_box.hi[axis] - lo;
      if (!(extent > 0)) continue;
      const float scale = float(bins) / extent;
      std::fill(bin_box.begin(), bin_box.end(), Bounds{});
      std::fill(bin_count.begin(), bin_count.end(), 0u);
      for (std::uint32_t i = begin; i < end; ++i) {
        const std::uint32_t id = ids_[i];
        const auto b = bin_of(centroids_[id][axis], lo, scale, bins);
        ++bin_count[b];
        bin_box[b] = merged(bin_box[b], boxes_[id]);
      }
      // right_*[p]: bins p .. bins-1.
      Bounds acc;
      std::uint32_t n = 0;
      for (std::uint32_t p = bins; p-- > 1;) {
        acc = merged(acc, bin_box[p]);
        n += bin_count[p];
        right_box[p] = acc;
        right_count[p] = n;
      }
      acc = Bounds{};
      n = 0;
      for (std::uint32_t p = 1; p < bins; ++p) {
        acc = merged(acc, bin_box[p - 1]);
        n += bin_count[p - 1];
        if (n == 0 || right_count[p] == 0) continue;
        const double cost = detail::box_area(acc) * n + detail::box_area(right_box[p]) * right_count[p];
        if (cost < best_cost) {
          best_cost = cost;
          best_axis = axis;
          best_plane = p;
        }
      }
    }
    const double area = detail::box_area(box);
    const double leaf_cost = double(options_.intersection_cost) * count;
    if (best_axis < 0) return count <= options_.max_leaf_size ? begin : median();
    const double split_cost =
        options_.traversal_cost + (area > 0 ? options_.intersection_cost * best_cost / area : leaf_cost);
    if (count <= options_.max_leaf_size && leaf_cost <= split_cost) return begin;
    const float lo = centroid_box.lo[best_axis];
    const float scale = float(bins) / (centroid_box.hi[best_axis] - lo);
    const auto mid = std::partition(ids_.begin() + begin, ids_.begin() + end, [&](std::uint32_t id) {
      return bin_of(centroids_[id][best_axis], lo, scale, bins) < best_plane;
    });
    return static_cast<std::uint32_t>(mid - ids_.begin());
  }

  static std::uint32_t bin_of(float c, float lo, float scale, std::uint32_t bins) {
    const float f = (c - lo) * scale;
    return f <= 0 ? 0u : std::min(bins - 1, static_cast<std::uint32_t>(f));
  }

  BvhBuildOptions options_;
  std::vector<Bounds> boxes_;
  std::vector<Vec3> centroids_;
  std::vector<std::uint32_t> ids_;

 public:
  // The wide tree: each node takes its binary node's two children, then
  // repeatedly opens the interior child with the largest surface area (its
  // two children take its place, keeping space order) until it has `arity`
  // children or none can be opened.
  static void collapse(const BinaryNode& root, unsigned arity, Bvh& bvh) {
    emit(root, 0, arity, bvh);
  }

 private:
  static std::uint32_t emit(const BinaryNode& binary, std::uint16_t level, unsigned arity, Bvh& bvh) {
    const auto index = static_cast<std::uint32_t>(bvh.nodes_.size());
    bvh.nodes_.push_back({});
    std::vector<const BinaryNode*> kids;
    if (binary.is_leaf()) {
      kids.push_back(&binary);  // a root that is one leaf: a node with one leaf child
    } else {
      kids = {binary.left.get(), binary.right.get()};
      while (kids.size() < arity) {
        int open = -1;
        double largest = -1;
        for (std::size_t k = 0; k < kids.size(); ++k) {
          if (kids[k]->is_leaf()) continue;
          const double a = detail::box_area(kids[k]->box);
          if (a > largest) {
            largest = a;
            open = static_cast<int>(k);
          }
        }
        if (open < 0) break;
        const BinaryNode* opened = kids[open];
        kids[open] = opened->left.get();
        kids.insert(kids.begin() + open + 1, opened->right.get());
      }
    }
    const auto first = static_cast<std::uint32_t>(bvh.children_.size());
    bvh.nodes_[index] = {first, static_cast<std::uint16_t>(kids.size()), level};
    bvh.children_.resize(first + kids.size());
    for (std::size_t k = 0; k < kids.size(); ++k) {
      BvhChild child;
      child.box = kids[k]->box;
      if (kids[k]->is_leaf()) {
        child.index = kids[k]->first;
        child.count = kids[k]->count;
      } else {
        child.index = emit(*kids[k], static_cast<std::uint16_t>(level + 1), arity, bvh);
      }
      bvh.children_[first + k] = child;
    }
    return index;
  }
};

namespace {

// One node's quantization: per axis the smallest power-of-two step whose
// 255 steps span the node box, grown while float rounding would leave an
// exact box outside its dequantized one.
void quantize_node(const BvhNode& node, std::vector<BvhChild>& children, std::vector<Bounds>& exact,
                   BvhQuantization& q) {
  Bounds box;
  for (std::uint32_t k = 0; k < node.child_count; ++k) box = merged(box, exact[node.first_child + k]);
  q.origin = box.lo;
  for (int axis = 0; axis < 3; ++axis) {
    const double extent = double(box.hi[axis]) - box.lo[axis];
    int e = extent > 0 ? static_cast<int>(std::ceil(math::log2(extent / 255.0))) : 0;
    for (int attempt = 0;; ++attempt, ++e) {
      if (attempt > 64) throw std::logic_error("BVH: no quantization step contains the child boxes");
      const float step = std::ldexp(1.0f, e);
      bool contains = true;
      for (std::uint32_t k = 0; k < node.child_count && contains; ++k) {
        const Bounds& exact_box = exact[node.first_child + k];
        double qlo = std::floor((double(exact_box.lo[axis]) - q.origin[axis]) / step);
        double qhi = std::ceil((double(exact_box.hi[axis]) - q.origin[axis]) / step);
        qlo = std::clamp(qlo, 0.0, 255.0);
        qhi = std::clamp(qhi, 0.0, 255.0);
        float lo = q.origin[axis] + float(qlo) * step;
        float hi = q.origin[axis] + float(qhi) * step;
        while (lo > exact_box.lo[axis] && qlo > 0) lo = q.origin[axis] + float(--qlo) * step;
        while (hi < exact_box.hi[axis] && qhi < 255) hi = q.origin[axis] + float(++qhi) * step;
        if (lo > exact_box.lo[axis] || hi < exact_box.hi[axis]) {
          contains = false;
          break;
        }
        children[node.first_child + k].box.lo[axis] = lo;
        children[node.first_child + k].box.hi[axis] = hi;
      }
      if (contains) {
        q.exponent[axis] = static_cast<std::int16_t>(e);
        break;
      }
    }
  }
}

}  // namespace

Bvh Bvh::build(std::span<const Triangle> triangles, unsigned arity, bool compressed, const BvhBuildOptions& options) {
  if (arity != 2 && arity != 4 && arity != 8) throw std::invalid_argument("BVH arity must be 2, 4 or 8");
  const auto start = std::chrono::steady_clock::now();
  const std::clock_t cpu_start = std::clock();
  Bvh bvh;
  bvh.arity_ = arity;
  bvh.compressed_ = compressed;
  BvhBuilder builder(triangles, options);
  const auto root = builder.build_binary();
  bvh.primitives_ = builder.take_ids();
  if (root) {
    bvh.bounds_ = root->box;
    BvhBuilder::collapse(*root, arity, bvh);
  }
  if (compressed) {
    bvh.exact_boxes_.reserve(bvh.children_.size());
    for (const auto& c : bvh.children_) bvh.exact_boxes_.push_back(c.box);
    bvh.quantizations_.resize(bvh.nodes_.size());
    for (std::size_t i = 0; i < bvh.nodes_.size(); ++i) {
      quantize_node(bvh.nodes_[i], bvh.children_, bvh.exact_boxes_, bvh.quantizations_[i]);
    }
  }
  // Figures, and the SAH cost of the tree as traversal sees it.
  KdTreeStats& s = bvh.stats_;
  s.nodes = s.interior = bvh.nodes_.size();
  const double root_area = detail::box_area(bvh.bounds_);
  double cost = 0;
  for (const auto& node : bvh.nodes_) {
    if (s.nodes_per_level.size() <= node.level) s.nodes_per_level.resize(node.level + 1u, 0);
    ++s.nodes_per_level[node.level];
    s.depth = std::max<std::uint32_t>(s.depth, node.level);
    Bounds box;
    for (std::uint32_t k = 0; k < node.child_count; ++k) {
      const BvhChild& c = bvh.children_[node.first_child + k];
      box = merged(box, c.box);
      if (!c.is_leaf()) continue;
      ++s.leaves;
      s.primitive_references += c.count;
      if (root_area > 0) cost += options.intersection_cost * c.count * detail::box_area(c.box) / root_area;
    }
    if (root_area > 0) cost += options.traversal_cost * detail::box_area(box) / root_area;
  }
  s.depth_limit = static_cast<int>(kBvhMaxLevels);
  s.mean_leaf_size = s.leaves ? double(s.primitive_references) / double(s.leaves) : 0;
  s.mean_nonempty_leaf_size = s.mean_leaf_size;
  s.sah_cost = cost;
  s.build_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  s.build_cpu_seconds = double(std::clock() - cpu_start) / CLOCKS_PER_SEC;
  return bvh;
}

TreeShape Bvh::shape() const {
  TreeShape shape;
  shape.level.reserve(nodes_.size());
  shape.area.reserve(nodes_.size());
  shape.child_begin.reserve(nodes_.size() + 1);
  for (const auto& node : nodes_) {
    shape.level.push_back(node.level);
    shape.child_begin.push_back(static_cast<std::uint32_t>(shape.children.size()));
    Bounds box;
    for (std::uint32_t k = 0; k < node.child_count; ++k) {
      const BvhChild& c = children_[node.first_child + k];
      box = merged(box, c.box);
      if (!c.is_leaf()) shape.children.push_back(c.index);
    }
    shape.area.push_back(static_cast<float>(detail::box_area(box)));
  }
  shape.child_begin.push_back(static_cast<std::uint32_t>(shape.children.size()));
  return shape;
}

}  // namespace nodetrace::tracer
