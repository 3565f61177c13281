// The seeded draws of the differential tests' generators: `below` on
// std::mt19937_64, whose sequence the standard fixes, so that a seed means
// the same case on every host.
#pragma once

#include <array>
#include <cstdint>
#include <random>

namespace nodetrace::testing {

class Draw {
 public:
  explicit Draw(std::uint64_t seed) : random_(seed * 0x9E3779B97F4A7C15ull + 12345) {}
  std::uint64_t below(std::uint64_t n) { return n == 0 ? 0 : random_() % n; }
  std::uint64_t between(std::uint64_t lo, std::uint64_t hi) { return lo + below(hi - lo + 1); }
  bool chance(int percent) { return below(100) < static_cast<std::uint64_t>(percent); }
  template <typename T, std::size_t N>
  T pick(const std::array<T, N>& items) {
    return items[below(N)];
  }

 private:
  std::mt19937_64 random_;
};

}  // namespace nodetrace::testing
