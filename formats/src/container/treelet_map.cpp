// The treelet holding an address (treelet_map.hpp).
#include "nodetrace/formats/container/treelet_map.hpp"

#include <algorithm>

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

}  // namespace nodetrace::formats
