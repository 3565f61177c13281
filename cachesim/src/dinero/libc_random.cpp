#include "libc_random.hpp"

namespace nodetrace::cachesim::detail {

LibcRandom::LibcRandom(std::uint32_t seed) {
  std::array<std::uint32_t, 34> r{};
  r[0] = seed == 0 ? 1 : seed;  // glibc takes seed 0 as 1
  for (int i = 1; i < 31; ++i) {
    // 16807 * r mod (2^31 - 1), kept positive as glibc does with signed words.
    const std::int64_t next = (16807 * static_cast<std::int64_t>(static_cast<std::int32_t>(r[i - 1]))) %
                              2147483647;
    r[i] = static_cast<std::uint32_t>(next < 0 ? next + 2147483647 : next);
  }
  for (int i = 31; i < 34; ++i) r[i] = r[i - 31];
  // ring_ holds r[3] .. r[33]: at_ = 0 is r[i-31] for i = 34.
  for (int i = 0; i < 31; ++i) ring_[i] = r[i + 3];
  at_ = 0;
  // The first 310 values (r[34] .. r[343]) are discarded.
  for (int i = 34; i < 344; ++i) next();
}

}  // namespace nodetrace::cachesim::detail
