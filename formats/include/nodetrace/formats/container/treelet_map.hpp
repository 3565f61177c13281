// The treelet map of one animation frame (issue 51): where the trace's
// treelets lie, so a simulator can prefetch a whole treelet when a ray
// enters it. A trace rendered with `--layout treelet` carries one per
// animation frame (the tree is rebuilt per frame); delivered with that
// frame's marker (AnimationFrameMarker::treelets). FORMAT.md gives its bytes.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

namespace nodetrace::formats {

// Bytes [first, first + bytes) of the node array hold one treelet.
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

}  // namespace nodetrace::formats
