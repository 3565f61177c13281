// Internal: the sequence of glibc's random() after srandom(1), which is what
// Dinero IV draws from (it never seeds it) for random replacement and for
// -pfabort. One generator serves a whole hierarchy, in the order Dinero IV
// makes its calls, so the same choices come out.
//
// glibc's default generator is an additive lagged Fibonacci one over 34
// words: r[0] = seed, r[i] = 16807 * r[i-1] mod (2^31 - 1) for i < 31,
// r[i] = r[i-31] for 31 <= i < 34, then r[i] = r[i-3] + r[i-31] (mod 2^32);
// the k-th output (from 0) is r[k + 344] >> 1.
#pragma once

#include <array>
#include <cstdint>

namespace nodetrace::cachesim::detail {

class LibcRandom {
 public:
  explicit LibcRandom(std::uint32_t seed = 1);
  // The next value in 0 .. 2^31 - 1.
  std::uint32_t next() {
    const std::uint32_t value = ring_[(at_ + 31 - 3) % 31] + ring_[at_];
    ring_[at_] = value;
    at_ = (at_ + 1) % 31;
    return value >> 1;
  }

 private:
  // The last 31 words r[i-31] .. r[i-1]; ring_[at_] is r[i-31].
  std::array<std::uint32_t, 31> ring_{};
  unsigned at_ = 0;
};

}  // namespace nodetrace::cachesim::detail
