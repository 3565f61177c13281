#include "nodetrace/tracer/accel/layout.hpp"

#include <algorithm>
#include <deque>
#include <queue>
#include <stdexcept>

#include "accel/box_test.hpp"
#include "nodetrace/base/huge_pages.hpp"

namespace nodetrace::tracer {

std::string_view layout_name(LayoutKind kind) {
  switch (kind) {
    case LayoutKind::Dfl: return "dfl";
    case LayoutKind::Bfl: return "bfl";
    case LayoutKind::Hybrid: return "hybrid";
    case LayoutKind::Veb: return "veb";
    case LayoutKind::Treelet: return "treelet";
  }
  return "dfl";
}

std::optional<LayoutKind> parse_layout_name(std::string_view name) {
  for (auto kind : {LayoutKind::Dfl, LayoutKind::Bfl, LayoutKind::Hybrid, LayoutKind::Veb, LayoutKind::Treelet}) {
    if (layout_name(kind) == name) return kind;
  }
  return std::nullopt;
}

std::uint32_t treelet_nodes_for(std::uint32_t treelet_bytes, std::uint32_t node_size) {
  return std::max<std::uint32_t>(1, node_size ? treelet_bytes / node_size : 1);
}

TreeShape kdtree_shape(const KdTree& tree) {
  const auto& nodes = tree.nodes();
  TreeShape shape;
  base::reserve_on_huge_pages(shape.level, nodes.size());
  base::reserve_on_huge_pages(shape.area, nodes.size());
  base::reserve_on_huge_pages(shape.child_begin, nodes.size() + 1);
  base::reserve_on_huge_pages(shape.children, nodes.size());  // two per inner node, fewer than the nodes
  shape.level.resize(nodes.size());
  shape.area.resize(nodes.size());
  std::vector<Bounds> boxes;
  base::reserve_on_huge_pages(boxes, nodes.size());
  boxes.resize(nodes.size());
  if (!nodes.empty()) boxes[0] = tree.bounds();
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    const KdNode& n = nodes[i];
    shape.level[i] = n.level;
    shape.area[i] = static_cast<float>(detail::box_area(boxes[i]));
    shape.child_begin.push_back(static_cast<std::uint32_t>(shape.children.size()));
    if (n.is_leaf()) continue;
    shape.children.push_back(n.left);
    shape.children.push_back(n.right);
    // Pre-order: children come after their parent, so their boxes are set
    // before they are read.
    Bounds below = boxes[i], above = boxes[i];
    below.hi[n.axis] = n.split;
    above.lo[n.axis] = n.split;
    boxes[n.left] = below;
    boxes[n.right] = above;
  }
  shape.child_begin.push_back(static_cast<std::uint32_t>(shape.children.size()));
  return shape;
}

namespace {

class SlotAssigner {
 public:
  explicit SlotAssigner(const TreeShape& shape) : shape_(shape), slots_(shape.size(), kUnassigned) {}

  // Pre-order, first child next, over the subtree at `root`.
  void depth_first(std::uint32_t root) {
    std::vector<std::uint32_t> stack{root};
    while (!stack.empty()) {
      const std::uint32_t n = stack.back();
      stack.pop_back();
      assign(n);
      const auto kids = shape_.children_of(n);
      for (auto it = kids.rbegin(); it != kids.rend(); ++it) stack.push_back(*it);
    }
  }

  // Level order over the nodes of levels < `stop_level`; returns the nodes at
  // `stop_level` in the order the walk meets them (the BFL order of their slots).
  std::vector<std::uint32_t> breadth_first(std::uint32_t stop_level) {
    std::vector<std::uint32_t> frontier;
    if (shape_.size() == 0) return frontier;
    std::deque<std::uint32_t> queue{0};
    while (!queue.empty()) {
      const std::uint32_t n = queue.front();
      queue.pop_front();
      if (shape_.level[n] >= stop_level) {
        frontier.push_back(n);
        continue;
      }
      assign(n);
      for (auto c : shape_.children_of(n)) queue.push_back(c);
    }
    return frontier;
  }

  // Van Emde Boas order of the nodes within `height` levels below `root`.
  void van_emde_boas(std::uint32_t root, std::uint32_t height) {
    if (height <= 1 || shape_.children_of(root).empty()) {
      assign(root);
      return;
    }
    const std::uint32_t top = height / 2;
    van_emde_boas(root, top);
    // The roots of the bottom trees, in stored child order.
    std::vector<std::uint32_t> bottoms;
    collect_at_depth(root, top, bottoms);
    for (auto b : bottoms) van_emde_boas(b, height - top);
  }

  // Treelets (Aila and Karras 2010, grown top down): a treelet starts at a
  // root and repeatedly takes, of the children of its members, the one whose
  // box has the largest surface area (the likeliest to be visited; ties: the
  // lower node index) until it holds `capacity` nodes or has no child left.
  // The children it leaves out root the next treelets, in the order the
  // treelets are formed (a queue), and each treelet's nodes take
  // consecutive slots in the order they joined.
  std::vector<std::uint32_t> treelets(std::uint32_t capacity) {
    std::vector<std::uint32_t> first_slots;
    if (shape_.size() == 0) return first_slots;
    std::deque<std::uint32_t> roots{0};
    struct Candidate {
      float area;
      std::uint32_t node;
      bool operator<(const Candidate& o) const { return area < o.area || (area == o.area && node > o.node); }
    };
    std::vector<std::uint32_t> members;
    while (!roots.empty()) {
      const std::uint32_t root = roots.front();
      roots.pop_front();
      first_slots.push_back(next_);
      std::priority_queue<Candidate> frontier;
      frontier.push({shape_.area[root], root});
      members.clear();
      while (!frontier.empty() && members.size() < capacity) {
        const std::uint32_t n = frontier.top().node;
        frontier.pop();
        members.push_back(n);
        assign(n);
        for (auto c : shape_.children_of(n)) frontier.push({shape_.area[c], c});
      }
      // What is left out, largest first, roots later treelets.
      std::vector<Candidate> rest;
      for (; !frontier.empty(); frontier.pop()) rest.push_back(frontier.top());
      for (const auto& c : rest) roots.push_back(c.node);
    }
    return first_slots;
  }

  std::uint32_t height() const {
    std::uint32_t deepest = 0;
    for (const auto l : shape_.level) deepest = std::max<std::uint32_t>(deepest, l);
    return shape_.size() == 0 ? 0 : deepest + 1;
  }

  std::vector<std::uint32_t> take() {
    for (auto s : slots_) {
      if (s == kUnassigned) throw std::logic_error("layout left a node without a slot");
    }
    return std::move(slots_);
  }

 private:
  static constexpr std::uint32_t kUnassigned = 0xFFFFFFFFu;

  void assign(std::uint32_t n) {
    if (slots_[n] != kUnassigned) throw std::logic_error("layout gave a node two slots");
    slots_[n] = next_++;
  }

  void collect_at_depth(std::uint32_t root, std::uint32_t depth, std::vector<std::uint32_t>& out) {
    const std::uint32_t target = shape_.level[root] + depth;
    std::vector<std::uint32_t> stack{root};
    while (!stack.empty()) {
      const std::uint32_t n = stack.back();
      stack.pop_back();
      if (shape_.level[n] == target) {
        out.push_back(n);
      } else {
        const auto kids = shape_.children_of(n);
        for (auto it = kids.rbegin(); it != kids.rend(); ++it) stack.push_back(*it);
      }
    }
  }

  const TreeShape& shape_;
  std::vector<std::uint32_t> slots_;
  std::uint32_t next_ = 0;
};

}  // namespace

Layout make_layout(const TreeShape& shape, LayoutKind kind, std::uint32_t split_level, std::uint32_t treelet_nodes) {
  Layout layout;
  layout.kind = kind;
  SlotAssigner assigner(shape);
  if (shape.size() != 0) {
    switch (kind) {
      case LayoutKind::Dfl:
        assigner.depth_first(0);
        break;
      case LayoutKind::Bfl:
        assigner.breadth_first(0xFFFFFFFFu);
        break;
      case LayoutKind::Hybrid: {
        layout.split_level = split_level;
        // The paper's deque walk: BFL above K; the level-K roots, in BFL order,
        // each followed by its whole subtree in DFL.
        for (auto root : assigner.breadth_first(split_level)) assigner.depth_first(root);
        break;
      }
      case LayoutKind::Veb:
        assigner.van_emde_boas(0, assigner.height());
        break;
      case LayoutKind::Treelet:
        layout.treelet_first_slot = assigner.treelets(std::max<std::uint32_t>(1, treelet_nodes));
        break;
    }
  }
  layout.slot_of_node = assigner.take();
  return layout;
}

Layout make_layout(const KdTree& tree, LayoutKind kind, std::uint32_t split_level, std::uint32_t treelet_nodes) {
  return make_layout(kdtree_shape(tree), kind, split_level, treelet_nodes);
}

}  // namespace nodetrace::tracer
