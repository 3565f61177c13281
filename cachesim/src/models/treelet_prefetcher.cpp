#include "models/treelet_prefetcher.hpp"

#include <algorithm>

namespace nodetrace::cachesim {

std::optional<PrefetchRange> treelet_prefetch_range(const formats::TreeletMap& map, std::uint64_t block_first,
                                                    std::uint64_t block_bytes, std::uint64_t limit) {
  const auto& treelets = map.treelets;
  // The first treelet that ends after the block's first byte: it holds that
  // byte, or begins after it (then it must begin inside the block).
  const auto found = std::upper_bound(treelets.begin(), treelets.end(), block_first,
                                      [](std::uint64_t address, const formats::TreeletRange& treelet) {
                                        return address < treelet.first + treelet.bytes;
                                      });
  if (found == treelets.end()) return std::nullopt;
  if (found->first > block_first && found->first - block_first >= block_bytes) return std::nullopt;
  std::uint64_t end = found->first + found->bytes;
  if (limit != 0 && end - block_first > limit) end = block_first + limit;
  return PrefetchRange{block_first, end};
}

}  // namespace nodetrace::cachesim
