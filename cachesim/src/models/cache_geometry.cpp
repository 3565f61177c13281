#include "nodetrace/cachesim/models/cache_geometry.hpp"

#include <fmt/format.h>

#include <bit>

#include "nodetrace/base/error.hpp"

namespace nodetrace::cachesim {

std::string_view policy_name(ReplacementPolicy policy) {
  switch (policy) {
    case ReplacementPolicy::Lru: return "lru";
    case ReplacementPolicy::Fifo: return "fifo";
    case ReplacementPolicy::Random: return "random";
    case ReplacementPolicy::Plru: return "plru";
    case ReplacementPolicy::Srrip: return "srrip";
    case ReplacementPolicy::Brrip: return "brrip";
    case ReplacementPolicy::Drrip: return "drrip";
    case ReplacementPolicy::Opt: return "opt";
  }
  return "lru";
}

std::optional<ReplacementPolicy> parse_policy_name(std::string_view name) {
  if (name == "lru" || name == "l") return ReplacementPolicy::Lru;
  if (name == "fifo" || name == "f") return ReplacementPolicy::Fifo;
  if (name == "random" || name == "r") return ReplacementPolicy::Random;
  for (const ReplacementPolicy policy : {ReplacementPolicy::Plru, ReplacementPolicy::Srrip, ReplacementPolicy::Brrip,
                                         ReplacementPolicy::Drrip, ReplacementPolicy::Opt}) {
    if (name == policy_name(policy)) return policy;
  }
  return std::nullopt;
}

bool dinero_has_policy(ReplacementPolicy policy) {
  return policy == ReplacementPolicy::Lru || policy == ReplacementPolicy::Fifo ||
         policy == ReplacementPolicy::Random;
}

bool misses_as_lru(ReplacementPolicy policy, std::uint32_t assoc) {
  if (policy == ReplacementPolicy::Opt) return false;  // MIN may leave a block out
  return assoc == 1 || policy == ReplacementPolicy::Lru || (policy == ReplacementPolicy::Plru && assoc == 2);
}

char dinero_policy_letter(ReplacementPolicy policy) { return policy_name(policy)[0]; }

void validate_geometry(const CacheGeometry& g, std::string_view what) {
  auto fail = [&](const std::string& problem) {
    throw base::UsageError(fmt::format("{}: {}", what, problem));
  };
  if (g.size == 0 || !std::has_single_bit(g.size)) {
    fail(fmt::format("size {} is not a power of two", g.size));
  }
  if (g.block_size == 0 || !std::has_single_bit(g.block_size)) {
    fail(fmt::format("block size {} is not a power of two", g.block_size));
  }
  if (g.size < g.block_size) {
    fail(fmt::format("size {} is smaller than the block size {}", g.size, g.block_size));
  }
  if (g.assoc == 0) fail("associativity must be at least 1");
  const std::uint64_t blocks = g.size / g.block_size;
  if (g.assoc > blocks) {
    fail(fmt::format("associativity {} is above the {} blocks of the cache", g.assoc, blocks));
  }
  if (g.replacement == ReplacementPolicy::Plru && !std::has_single_bit(g.assoc)) {
    fail(fmt::format("--policy plru needs a power-of-two number of ways (1, 2, 4, 8, ...), not {}", g.assoc));
  }
  // Powers of two: a multiple of block x ways is a power-of-two number of sets.
  if (g.size % (std::uint64_t{g.block_size} * g.assoc) != 0) {
    fail(fmt::format("size {} is not a multiple of block size {} x associativity {}", g.size,
                     g.block_size, g.assoc));
  }
}

}  // namespace nodetrace::cachesim
