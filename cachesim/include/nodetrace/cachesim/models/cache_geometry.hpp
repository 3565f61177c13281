// The cache vocabulary shared by the Dinero-IV-exact engine and the node
// caches: one replacement policy enum, one geometry, one validator.
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>

namespace nodetrace::cachesim {

// Dinero IV's -lN-Trepl l|f|r (random draws Dinero IV's sequence: glibc's
// random() after srandom(1), one generator per cache), then the policies
// Dinero IV does not have (cachesim run only; docs/guide/replacement-policies.md):
// tree pseudo-LRU, static / bimodal / dynamic re-reference interval
// prediction, and Belady's MIN.
enum class ReplacementPolicy : std::uint8_t { Lru, Fifo, Random, Plru, Srrip, Brrip, Drrip, Opt };

// lru, fifo, random, plru, srrip, brrip, drrip, opt
std::string_view policy_name(ReplacementPolicy policy);
std::optional<ReplacementPolicy> parse_policy_name(std::string_view name);  // also l, f, r
// The names parse_policy_name takes, for error messages.
inline constexpr std::string_view kPolicyNames = "lru, fifo, random, plru, srrip, brrip, drrip, opt";
// Whether Dinero IV has the policy (lru, fifo, random).
bool dinero_has_policy(ReplacementPolicy policy);
// Dinero IV's -l1-urepl letter: l, f, r.
char dinero_policy_letter(ReplacementPolicy policy);
// Whether a cache of `assoc` ways under `policy` misses exactly as LRU does
// (every policy but opt at 1 way, plru at 2): such caches are answered by LRU's models.
bool misses_as_lru(ReplacementPolicy policy, std::uint32_t assoc);

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
// plru needs a power-of-two number of ways (also an error here).
void validate_geometry(const CacheGeometry& geometry, std::string_view what);

}  // namespace nodetrace::cachesim
