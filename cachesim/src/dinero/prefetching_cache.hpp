// Internal: the cache model of a `cachesim run` configuration with a fetch
// policy other than demand (config_simulator.cpp): one cache of Dinero IV's
// engine, so prefetches, and the replacement they cause, are Dinero IV's.
// The stack groups, which answer many configurations in one pass, stay
// demand-only; such a configuration is simulated alone.
#pragma once

#include <cstdint>
#include <memory>

#include "nodetrace/cachesim/dinero/engine.hpp"
#include "nodetrace/cachesim/models/cache_geometry.hpp"
#include "nodetrace/formats/record/record.hpp"

namespace nodetrace::cachesim {

namespace detail {
class Cache;
class LibcRandom;
}  // namespace detail

class PrefetchingCache {
 public:
  // `distance`: the prefetch distance in blocks (no sub-blocks here).
  PrefetchingCache(const CacheGeometry& geometry, FetchPolicy fetch, std::uint32_t distance);
  ~PrefetchingCache();
  PrefetchingCache(PrefetchingCache&&) noexcept;
  PrefetchingCache& operator=(PrefetchingCache&&) noexcept;

  // A demand fetch of block number `block` by a reference of `type` (reads
  // and instruction fetches prefetch; writes and misc references do not, as
  // in Dinero IV). Returns whether it missed.
  bool access(std::uint64_t block, formats::AccessType type);
  bool access(std::uint64_t block) { return access(block, formats::AccessType::Read); }
  void invalidate(std::uint64_t block);

 private:
  std::unique_ptr<detail::LibcRandom> random_;
  std::unique_ptr<detail::Cache> cache_;
  unsigned shift_;
};

}  // namespace nodetrace::cachesim
