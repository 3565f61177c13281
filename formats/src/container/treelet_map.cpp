// The treelet holding an address, and the checks every map passes
// (treelet_map.hpp).
#include "nodetrace/formats/container/treelet_map.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "container/container.hpp"
#include "container/treelet_map_codec.hpp"
#include "nodetrace/base/error.hpp"

namespace nodetrace::formats {

std::optional<std::size_t> TreeletMap::treelet_of(std::uint64_t address) const {
  // The last treelet that begins at or before the address.
  const auto after = std::upper_bound(treelets.begin(), treelets.end(), address,
                                      [](std::uint64_t a, const TreeletRange& t) { return a < t.first; });
  if (after == treelets.begin()) return std::nullopt;
  const auto& holder = *(after - 1);
  if (address - holder.first >= holder.bytes) return std::nullopt;
  return static_cast<std::size_t>(after - 1 - treelets.begin());
}

NodeAddressRange node_address_range(std::uint64_t node_base, std::uint64_t nodes, std::uint64_t node_size) {
  constexpr std::uint64_t kTop = ~std::uint64_t{0};
  const std::uint64_t span = node_size != 0 && nodes > kTop / node_size ? kTop : nodes * node_size;
  return {node_base, span > kTop - node_base ? kTop : node_base + span};
}

void check_treelet_map(const TreeletMap& map, NodeAddressRange nodes) {
  const auto& treelets = map.treelets;
  for (std::size_t i = 0; i < treelets.size(); ++i) {
    const TreeletRange& t = treelets[i];
    const std::string which = fmt::format("treelet {} of {}", i + 1, treelets.size());
    if (t.bytes == 0) throw base::FormatError(fmt::format("{} (at {:#x}) is empty", which, t.first));
    if (t.first < nodes.begin || t.first > nodes.end || t.bytes > nodes.end - t.first) {
      throw base::FormatError(fmt::format("{}, {:#x} + {} bytes, lies outside the frame's node addresses "
                                          "[{:#x}, {:#x})",
                                          which, t.first, t.bytes, nodes.begin, nodes.end));
    }
    if (i == 0) continue;
    const TreeletRange& before = treelets[i - 1];
    if (t.first < before.first) {
      throw base::FormatError(fmt::format("{} begins at {:#x}, before treelet {} at {:#x}: the map is not in "
                                          "increasing address order",
                                          which, t.first, i, before.first));
    }
    if (t.first - before.first < before.bytes) {
      throw base::FormatError(fmt::format("{} begins at {:#x}, inside treelet {} ({:#x} + {} bytes): treelets "
                                          "overlap",
                                          which, t.first, i, before.first, before.bytes));
    }
  }
}

std::uint64_t treelet_map_frame_bytes(const TreeletMap& map) {
  return detail::kSkippableHeaderSize + detail::encode_treelet_map(map).size();
}

}  // namespace nodetrace::formats
