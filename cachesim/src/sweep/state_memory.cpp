#include "nodetrace/cachesim/sweep/state_memory.hpp"

namespace nodetrace::cachesim {

namespace {

constexpr std::uint32_t kScannedWays = 16;  // policy_cache.hpp's kScanWays
constexpr std::uint64_t kBytesPerScannedBlock = 8;
constexpr std::uint64_t kBytesPerIndexedBlock = 48;
// The retain set: a direct-mapped filter of 4 slots and a hash set of 2 a block.
constexpr std::uint64_t kBytesPerRetainedBlock = 4 * 8 + 2 * 12;

}  // namespace

std::uint64_t cache_state_bytes(const CacheGeometry& geometry) {
  const std::uint64_t blocks = geometry.size / geometry.block_size;
  return blocks * (geometry.assoc > kScannedWays ? kBytesPerIndexedBlock : kBytesPerScannedBlock);
}

std::uint64_t state_bytes(const std::vector<Configuration>& configs, const CacheGeometry* l2) {
  std::uint64_t total = 0;
  for (const Configuration& config : configs) {
    if (config.scheme == Scheme::Single) {
      total += cache_state_bytes({config.size, config.block, config.assoc, config.policy});
    } else {
      total += cache_state_bytes({config.low_size, config.block, config.assoc, config.policy});
      total += config.high_policy == HighPolicy::Retain
                   ? config.high_size / config.block * kBytesPerRetainedBlock
                   : cache_state_bytes({config.high_size, config.block, config.high_assoc, config.policy});
    }
    if (l2 != nullptr) total += cache_state_bytes(*l2);
  }
  return total;
}

}  // namespace nodetrace::cachesim
