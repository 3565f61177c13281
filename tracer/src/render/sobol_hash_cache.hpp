// The Sobol sampler's hashes (sobol.hpp) of the pixel being rendered. They
// depend on the frame, pixel, bounce and pair, not on the sample, so a pixel
// of spp samples computes each once instead of spp times: the Philox call
// that makes them was most of the sampler's cost. Kept per render worker
// (Renderer::Context); any order of pixels and samples gets the same numbers,
// the cache only saves work when a pixel's samples follow each other.
// Internal header.
#pragma once

#include <array>
#include <cstdint>

namespace nodetrace::tracer::detail {

// A pair's three hashes: the permutation of sample numbers, then the Owen
// scrambles of its first and second number.
struct SobolHashes {
  std::uint32_t permutation, first, second;
};

class SobolHashCache {
 public:
  // Bounces and pairs beyond these are computed each time (rare: deep paths).
  static constexpr std::uint32_t kBounces = 64, kPairs = 16;

  // The hashes of (frame, pixel, bounce, pair): `compute()` when not kept.
  template <class Compute>
  SobolHashes get(std::uint64_t frame, std::uint32_t pixel, std::uint32_t bounce, std::uint32_t pair,
                  const Compute& compute) {
    if (bounce >= kBounces || pair >= kPairs) return compute();
    if (stamp_ == 0 || frame != frame_ || pixel != pixel_) begin(frame, pixel);
    Entry& entry = entries_[bounce * kPairs + pair];
    if (entry.stamp != stamp_) entry = {compute(), stamp_};
    return entry.hashes;
  }

 private:
  // A new pixel: every entry of an older stamp is stale (0 is never a stamp).
  void begin(std::uint64_t frame, std::uint32_t pixel) {
    frame_ = frame, pixel_ = pixel;
    if (++stamp_ == 0) {
      entries_ = {};
      stamp_ = 1;
    }
  }

  struct Entry {
    SobolHashes hashes;
    std::uint32_t stamp;
  };
  std::array<Entry, kBounces * kPairs> entries_{};
  std::uint32_t stamp_ = 0;
  std::uint64_t frame_ = 0;
  std::uint32_t pixel_ = 0;
};

}  // namespace nodetrace::tracer::detail
