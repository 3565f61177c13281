// K-sizing: how many tree levels fit a high-level cache, given where the
// nodes of the top levels lie. The tracer sizes the hybrid layout's BFL part
// with it and cachesim resolves `--split-level auto` with it, so both agree.
#pragma once

#include <cstdint>
#include <span>

namespace nodetrace::base {

// Where the nodes of the top levels lie, for K-sizing.
struct LevelPlacement {
  std::uint64_t node_size = 8;
  std::uint64_t node_base = 0;
  std::uint64_t block = 1;  // bytes per cache block; 1 counts bytes
  // Levels < contiguous_levels lie one after another from node_base in level
  // order (the bfl layout, the hybrid layout's BFL part). A node of a deeper
  // level is counted as occupying blocks of its own: in DFL / vEB order its
  // neighbours are mostly of other levels, so this bounds what it occupies.
  std::uint32_t contiguous_levels = ~std::uint32_t{0};

  // Nodes of `node_size` bytes laid out contiguously in level order from 0,
  // counted in bytes: the BFL part of a hybrid layout being sized.
  static LevelPlacement contiguous_bytes(std::uint64_t node_size) {
    LevelPlacement placement;
    placement.node_size = node_size;
    return placement;
  }
};

// The largest K for which the nodes of levels < K occupy at most
// capacity_bytes / block blocks (docs/ARCHITECTURE.md, "K").
std::uint32_t split_level_for_capacity(std::span<const std::uint64_t> nodes_per_level,
                                       const LevelPlacement& placement, std::uint64_t capacity_bytes);

}  // namespace nodetrace::base
