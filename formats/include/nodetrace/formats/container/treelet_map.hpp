// The treelet map of one animation frame (issue 51): where the trace's
// treelets lie, so a simulator can prefetch a whole treelet when a ray
// enters it. A trace rendered with `--layout treelet` carries one per
// animation frame (the tree is rebuilt per frame); delivered with that
// frame's marker (AnimationFrameMarker::treelets). FORMAT.md 2.2.2 gives its
// bytes.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

namespace nodetrace::formats {

// Bytes [first, first + bytes) of the node array hold one treelet; `first`
// is a record address (node_base included).
struct TreeletRange {
  std::uint64_t first = 0;
  std::uint64_t bytes = 0;
  friend bool operator==(const TreeletRange&, const TreeletRange&) = default;
};

struct TreeletMap {
  // In increasing address order, none empty, none overlapping another.
  std::vector<TreeletRange> treelets;

  // The index of the treelet holding `address`; nullopt when none does.
  std::optional<std::size_t> treelet_of(std::uint64_t address) const;
  friend bool operator==(const TreeletMap&, const TreeletMap&) = default;
};

// The node addresses of one animation frame, [begin, end): node_base to
// node_base + nodes * node_size (the header's layout, the frame's marker).
struct NodeAddressRange {
  std::uint64_t begin = 0;
  std::uint64_t end = 0;
};
// Saturates at 2^64 - 1 rather than wrapping.
NodeAddressRange node_address_range(std::uint64_t node_base, std::uint64_t nodes, std::uint64_t node_size);

// Throws base::FormatError, naming the first treelet (1-based) that is
// empty, out of increasing address order, overlaps the one before it, or
// lies outside `nodes`. The message names neither the trace nor the frame:
// callers add them.
void check_treelet_map(const TreeletMap& map, NodeAddressRange nodes);

// The bytes of the skippable frame nodetrace's writer holds `map` in
// (FORMAT.md 2.2.2; another writer may encode the same map otherwise).
std::uint64_t treelet_map_frame_bytes(const TreeletMap& map);

}  // namespace nodetrace::formats
