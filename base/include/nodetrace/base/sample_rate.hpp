// How sampled runs choose what they simulate or render: a rate written "1/K"
// on the command line, and a seeded hash that picks one unit in each stratum
// of K. Shared by `tracer render --sample-rows` and `cachesim run
// --sample-windows / --sample-sets`, so both read rates and seeds alike.
#pragma once

#include <cstdint>
#include <string_view>

namespace nodetrace::base {

// "1/K" with K a whole number >= 1 -> K. Anything else (1/0, 3/2, abc, 0/4)
// throws UsageError naming `option`.
std::uint64_t parse_sample_rate(std::string_view text, std::string_view option);

// SplitMix64's finaliser (Steele, Lea and Flood 2014): a well-mixed 64-bit
// hash, the same on every host, so a seed picks the same units everywhere.
constexpr std::uint64_t mix64(std::uint64_t value) {
  value += 0x9e3779b97f4a7c15ULL;
  value = (value ^ (value >> 30)) * 0xbf58476d1ce4e5b9ULL;
  value = (value ^ (value >> 27)) * 0x94d049bb133111ebULL;
  return value ^ (value >> 31);
}

}  // namespace nodetrace::base
