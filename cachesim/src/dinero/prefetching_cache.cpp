#include "prefetching_cache.hpp"

#include <bit>

#include "dinero/engine_cache.hpp"
#include "dinero/libc_random.hpp"

namespace nodetrace::cachesim {

PrefetchingCache::PrefetchingCache(const CacheGeometry& geometry, FetchPolicy fetch,
                                   std::uint32_t distance)
    : random_(std::make_unique<detail::LibcRandom>()),
      shift_(static_cast<unsigned>(std::countr_zero(geometry.block_size))) {
  CacheConfig config;
  config.size = geometry.size;
  config.block_size = geometry.block_size;
  config.assoc = geometry.assoc;
  config.replacement = geometry.replacement;
  config.fetch = fetch;
  config.prefetch_distance = distance;
  cache_ = std::make_unique<detail::Cache>(config, *random_);
}

PrefetchingCache::~PrefetchingCache() = default;
PrefetchingCache::PrefetchingCache(PrefetchingCache&&) noexcept = default;
PrefetchingCache& PrefetchingCache::operator=(PrefetchingCache&&) noexcept = default;

bool PrefetchingCache::access(std::uint64_t block, formats::AccessType type) {
  // A byte at the block's start: the same hit or miss, and prefetch target,
  // as any reference within the block (a sub-block is a block here).
  detail::Ref ref;
  ref.address = block << shift_;
  ref.size = 1;
  ref.type = static_cast<std::uint8_t>(type);
  const std::uint64_t misses_before = cache_->stats.demand_misses();
  cache_->ref(ref);
  return cache_->stats.demand_misses() != misses_before;
}

void PrefetchingCache::invalidate(std::uint64_t block) {
  detail::Ref ref;
  ref.address = block << shift_;
  ref.size = 1;
  ref.type = detail::kInvalidate;
  cache_->ref(ref);
}

}  // namespace nodetrace::cachesim
