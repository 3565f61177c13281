// The cache vocabulary shared by the Dinero-IV-exact engine and the node
// caches: one replacement policy enum, one geometry, one validator.
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>

namespace nodetrace::cachesim {

// Dinero IV's -lN-Trepl l|f|r. Random is seeded and deterministic; its
// choices are not Dinero IV's (which uses the C library's random()).
enum class ReplacementPolicy : std::uint8_t { Lru, Fifo, Random };

std::string_view policy_name(ReplacementPolicy policy);  // lru, fifo, random
std::optional<ReplacementPolicy> parse_policy_name(std::string_view name);  // also l, f, r
// Dinero IV's -l1-urepl letter: l, f, r.
char dinero_policy_letter(ReplacementPolicy policy);

struct CacheGeometry {
  std::uint64_t size = 8192;  // bytes, a power of two
  std::uint32_t block_size = 8;  // bytes, a power of two
  std::uint32_t assoc = 1;       // ways; size / block_size is fully associative
  ReplacementPolicy replacement = ReplacementPolicy::Lru;
};

// Throws base::UsageError, "WHAT: ..." (e.g. "low-level cache of 4096
// bytes", "l1-dcache"), when the geometry cannot be built: sizes not powers
// of two, a block larger than the cache, associativity 0, above the blocks,
// or not dividing them into sets.
void validate_geometry(const CacheGeometry& geometry, std::string_view what);

}  // namespace nodetrace::cachesim
