// The path tracer's random numbers: counter-based, so each number depends on
// where it is used and on nothing else (not on threads, pixel order, rays in
// flight or sampled rows). Philox4x32-10 (Salmon et al., "Parallel random
// numbers: as easy as 1, 2, 3", SC 2011; Random123's header) maps a counter
// (pixel, sample, bounce << 16 | dimension / 4, animation frame's low 32
// bits) under the key (kPathSeed ^ --path-seed, animation frame's high 32 bits) to four
// 32-bit words; dimension d takes word d % 4. With --sampler sobol the
// numbers come from sobol.hpp instead, as counter-based. Internal header.
#pragma once

#include <Random123/philox.h>

#include <cstdint>

#include "nodetrace/tracer/render/integrator.hpp"
#include "render/sobol.hpp"
#include "render/sobol_hash_cache.hpp"

namespace nodetrace::tracer::detail {

inline constexpr std::uint32_t kPathSeed = 0x6e747261;  // "ntra": fixed, written in the trace header
inline constexpr std::uint32_t kSobolSeed = 0x736f626c;  // "sobl": the Sobol sampler's hashes

// Which number of a bounce: the bounce is the number of the ray the number
// decides (the camera ray is bounce 0, the ray leaving the first hit bounce 1).
enum PathDimension : std::uint32_t {
  kPixelX = 0,  // bounce 0: where in the pixel the camera ray passes
  kPixelY = 1,
  kLobe = 0,  // bounce >= 1: which lobe
  kDirection1 = 1,
  kDirection2 = 2,
  kFresnel = 3,   // reflection or refraction at a dielectric
  kRoulette = 4,  // Russian roulette before the ray
  kEmitterU = 5,  // next-event estimation at the ray's origin: which emitter and where on it
  kEmitterV = 6,
  // Next-event estimation at the ray's origin: which direction of the
  // environment map. 7 is left out so the pair is words 0 and 1 of one
  // Philox block (dimension / 4), as the other pairs are.
  kEnvironmentU = 8,
  kEnvironmentV = 9,
};

class PathRandom {
 public:
  PathRandom(std::uint64_t animation_frame, std::uint32_t pixel, std::uint32_t sample,
             PathSampler sampler = PathSampler::Independent, std::uint32_t samples_per_pixel = 1,
             std::uint32_t seed = 0, SobolHashCache* sobol_hashes = nullptr)
      : frame_(animation_frame),
        pixel_(pixel),
        sample_(sample),
        sampler_(sampler),
        spp_(samples_per_pixel),
        seed_(seed),
        sobol_hashes_(sobol_hashes) {}

  // A uniform float in [0, 1): the top 24 bits of the word, exactly.
  float uniform(std::uint32_t bounce, std::uint32_t dimension) const {
    if (sampler_ == PathSampler::Sobol) return sobol(bounce, dimension);
    return to_unit(philox_words(bounce, dimension)[dimension % 4]);
  }

  // uniform(bounce, first) and uniform(bounce, first + 1), the two numbers of
  // a 2D pair (the point in the pixel, a bounce direction, a point on an
  // emitter), drawn together: one Philox call (both words are of one block
  // of four) and, for Sobol, one set of hashes and one permuted index.
  struct Pair {
    float first, second;
  };
  Pair uniform_pair(std::uint32_t bounce, std::uint32_t first) const {
    if (sampler_ == PathSampler::Sobol) {
      const SobolHashes hashes = pair_hashes(bounce, first);
      const std::uint32_t index = permuted(sample_, spp_, hashes.permutation);
      return {to_unit(scrambled_sobol(index, 0, hashes.first)), to_unit(scrambled_sobol(index, 1, hashes.second))};
    }
    const r123::Philox4x32::ctr_type words = philox_words(bounce, first);
    return {to_unit(words[first % 4]), to_unit(words[(first + 1) % 4])};
  }

 private:
  static float to_unit(std::uint32_t word) { return static_cast<float>(word >> 8) * 0x1p-24f; }

  r123::Philox4x32::ctr_type philox_words(std::uint32_t bounce, std::uint32_t dimension) const {
    const r123::Philox4x32 philox;
    const r123::Philox4x32::ctr_type counter = {
        {pixel_, sample_, (bounce << 16) | (dimension / 4), static_cast<std::uint32_t>(frame_)}};
    const r123::Philox4x32::key_type key = {{kPathSeed ^ seed_, static_cast<std::uint32_t>(frame_ >> 32)}};
    return philox(counter, key);
  }

  // The hashes of a Sobol pair: Philox of (pixel, bounce, pair, frame), not
  // of the sample, so they are kept for the pixel's other samples.
  SobolHashes pair_hashes(std::uint32_t bounce, std::uint32_t pair) const {
    const auto compute = [&] {
      const r123::Philox4x32 philox;
      const r123::Philox4x32::ctr_type counter = {{pixel_, bounce, pair, static_cast<std::uint32_t>(frame_)}};
      const r123::Philox4x32::key_type key = {{kSobolSeed ^ seed_, static_cast<std::uint32_t>(frame_ >> 32)}};
      const r123::Philox4x32::ctr_type words = philox(counter, key);
      return SobolHashes{words[0], words[1], words[2]};
    };
    return sobol_hashes_ ? sobol_hashes_->get(frame_, pixel_, bounce, pair, compute) : compute();
  }

  // The second number of a 2D pair: Sobol dimension 1, with its first's index.
  static bool second_of_pair(std::uint32_t bounce, std::uint32_t dimension) {
    return bounce == 0 ? dimension == kPixelY : dimension == kDirection2 || dimension == kEmitterV ||
                                        dimension == kEnvironmentV;
  }

  float sobol(std::uint32_t bounce, std::uint32_t dimension) const {
    const bool second = second_of_pair(bounce, dimension);
    const std::uint32_t pair = second ? dimension - 1 : dimension;
    const SobolHashes hashes = pair_hashes(bounce, pair);
    const std::uint32_t index = permuted(sample_, spp_, hashes.permutation);
    return to_unit(scrambled_sobol(index, second ? 1 : 0, second ? hashes.second : hashes.first));
  }

  std::uint64_t frame_;
  std::uint32_t pixel_, sample_;
  PathSampler sampler_;
  std::uint32_t spp_;
  std::uint32_t seed_;            // --path-seed
  SobolHashCache* sobol_hashes_;  // the worker's, or none
};

}  // namespace nodetrace::tracer::detail
