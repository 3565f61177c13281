#include "render/treelet_map.hpp"

namespace nodetrace::tracer {

std::optional<formats::TreeletMap> treelet_map_of(const Layout& layout, const AddressMap& addresses) {
  if (layout.kind != LayoutKind::Treelet) return std::nullopt;
  formats::TreeletMap map;
  const auto& first = layout.treelet_first_slot;
  map.treelets.reserve(first.size());
  const std::uint64_t size = addresses.node_size;
  for (std::size_t i = 0; i < first.size(); ++i) {
    const std::uint64_t end = i + 1 < first.size() ? first[i + 1] : layout.slot_of_node.size();
    map.treelets.push_back({addresses.node_base + first[i] * size, (end - first[i]) * size});
  }
  return map;
}

}  // namespace nodetrace::tracer
