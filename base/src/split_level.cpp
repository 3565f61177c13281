#include "nodetrace/base/split_level.hpp"

#include <algorithm>

namespace nodetrace::base {

std::uint32_t split_level_for_capacity(std::span<const std::uint64_t> nodes_per_level,
                                       const LevelPlacement& placement, std::uint64_t capacity_bytes) {
  const std::uint64_t block = placement.block == 0 ? 1 : placement.block;
  const std::uint64_t node_size = placement.node_size == 0 ? 1 : placement.node_size;
  const std::uint64_t capacity = capacity_bytes / block;
  // A node on its own: aligned nodes and blocks of power-of-two sizes nest,
  // anything else may straddle one more block.
  const bool nested = placement.node_base % std::min(node_size, block) == 0 &&
                      (node_size % block == 0 || block % node_size == 0);
  const std::uint64_t blocks_per_node = nested ? std::max<std::uint64_t>(1, node_size / block)
                                               : node_size / block + 2;
  std::uint64_t contiguous_nodes = 0;
  std::uint64_t scattered_blocks = 0;
  std::uint32_t k = 0;
  for (const std::uint64_t count : nodes_per_level) {
    if (k < placement.contiguous_levels) {
      contiguous_nodes += count;
    } else {
      if (count > (capacity + 1) / blocks_per_node) break;
      scattered_blocks += count * blocks_per_node;
    }
    std::uint64_t blocks = scattered_blocks;
    if (contiguous_nodes > 0) {
      if (contiguous_nodes > (capacity_bytes + block) / node_size + 1) break;  // no overflow below
      const std::uint64_t first = placement.node_base / block;
      const std::uint64_t last = (placement.node_base + contiguous_nodes * node_size - 1) / block;
      blocks += last - first + 1;
    }
    if (blocks > capacity) break;
    ++k;
  }
  return k;
}

}  // namespace nodetrace::base
