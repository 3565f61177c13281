#include "nodetrace/tracer/accel/layout.hpp"

#include <deque>
#include <stdexcept>

#include "nodetrace/formats/container/metadata.hpp"

namespace nodetrace::tracer {

std::string_view layout_name(LayoutKind kind) {
  switch (kind) {
    case LayoutKind::Dfl: return "dfl";
    case LayoutKind::Bfl: return "bfl";
    case LayoutKind::Hybrid: return "hybrid";
    case LayoutKind::Veb: return "veb";
  }
  return "dfl";
}

std::optional<LayoutKind> parse_layout_name(std::string_view name) {
  for (auto kind : {LayoutKind::Dfl, LayoutKind::Bfl, LayoutKind::Hybrid, LayoutKind::Veb}) {
    if (layout_name(kind) == name) return kind;
  }
  return std::nullopt;
}

namespace {

class SlotAssigner {
 public:
  explicit SlotAssigner(const KdTree& tree)
      : nodes_(tree.nodes()), slots_(tree.nodes().size(), kUnassigned) {}

  // Pre-order, left child next, over the subtree at `root`.
  void depth_first(std::uint32_t root) {
    std::vector<std::uint32_t> stack{root};
    while (!stack.empty()) {
      const std::uint32_t n = stack.back();
      stack.pop_back();
      assign(n);
      if (!nodes_[n].is_leaf()) {
        stack.push_back(nodes_[n].right);
        stack.push_back(nodes_[n].left);
      }
    }
  }

  // Level order over the nodes of levels < `stop_level`; returns the nodes at
  // `stop_level` in the order the walk meets them (the BFL order of their slots).
  std::vector<std::uint32_t> breadth_first(std::uint32_t stop_level) {
    std::vector<std::uint32_t> frontier;
    if (nodes_.empty()) return frontier;
    std::deque<std::uint32_t> queue{0};
    while (!queue.empty()) {
      const std::uint32_t n = queue.front();
      queue.pop_front();
      if (nodes_[n].level >= stop_level) {
        frontier.push_back(n);
        continue;
      }
      assign(n);
      if (!nodes_[n].is_leaf()) {
        queue.push_back(nodes_[n].left);
        queue.push_back(nodes_[n].right);
      }
    }
    return frontier;
  }

  // Van Emde Boas order of the nodes within `height` levels below `root`.
  void van_emde_boas(std::uint32_t root, std::uint32_t height) {
    if (height <= 1 || nodes_[root].is_leaf()) {
      assign(root);
      return;
    }
    const std::uint32_t top = height / 2;
    van_emde_boas(root, top);
    // The roots of the bottom trees, left to right.
    std::vector<std::uint32_t> bottoms;
    collect_at_depth(root, top, bottoms);
    for (auto b : bottoms) van_emde_boas(b, height - top);
  }

  // Height of the subtree at the root, in levels.
  std::uint32_t height() const {
    std::uint32_t deepest = 0;
    for (const auto& n : nodes_) deepest = std::max<std::uint32_t>(deepest, n.level);
    return nodes_.empty() ? 0 : deepest + 1;
  }

  std::vector<std::uint32_t> take() {
    for (auto s : slots_) {
      if (s == kUnassigned) throw std::logic_error("layout left a node without a slot");
    }
    return std::move(slots_);
  }

 private:
  static constexpr std::uint32_t kUnassigned = 0xFFFFFFFFu;

  void assign(std::uint32_t n) { slots_[n] = next_++; }

  void collect_at_depth(std::uint32_t root, std::uint32_t depth, std::vector<std::uint32_t>& out) {
    const std::uint32_t target = nodes_[root].level + depth;
    std::vector<std::uint32_t> stack{root};
    while (!stack.empty()) {
      const std::uint32_t n = stack.back();
      stack.pop_back();
      if (nodes_[n].level == target) {
        out.push_back(n);
      } else if (!nodes_[n].is_leaf()) {
        stack.push_back(nodes_[n].right);
        stack.push_back(nodes_[n].left);
      }
    }
  }

  const std::vector<KdNode>& nodes_;
  std::vector<std::uint32_t> slots_;
  std::uint32_t next_ = 0;
};

}  // namespace

Layout make_layout(const KdTree& tree, LayoutKind kind, std::uint32_t split_level) {
  Layout layout;
  layout.kind = kind;
  SlotAssigner assigner(tree);
  if (!tree.nodes().empty()) {
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
    }
  }
  layout.slot_of_node = assigner.take();
  return layout;
}

}  // namespace nodetrace::tracer
