// What computes a pixel: the Whitted ray tracer (the paper's) or a path
// tracer, and the path tracer's settings with their limits.
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>

namespace nodetrace::tracer {

enum class Integrator : std::uint8_t { Whitted, Path };
std::string_view integrator_name(Integrator integrator);  // whitted, path
std::optional<Integrator> parse_integrator(std::string_view name);

// Samples per pixel: one by default, the smallest node-cache workload (a
// trace grows with the samples; raise it for images). At most 2^16.
inline constexpr std::uint32_t kDefaultSamplesPerPixel = 1;
inline constexpr std::uint32_t kMaxSamplesPerPixel = 1u << 16;
// Bounce rays after the camera ray: 5 by default (pbrt's default path depth:
// Russian roulette ends most paths before it). At most 64: beyond that every
// path has long met the roulette, and the bounce number fits the random
// generator's counter with room to spare.
inline constexpr int kDefaultMaxBounces = 5;
inline constexpr int kMaxBounces = 64;
// Russian roulette before every bounce ray from this one on (the third: the
// first bounces carry most of the light, as in pbrt). The path survives with
// probability min(0.95, largest throughput component) and is divided by it.
inline constexpr int kRouletteFromBounce = 3;
inline constexpr float kMaxSurvival = 0.95f;

// Where the path tracer's uniform numbers come from: independent
// (Philox, the default) or low-discrepancy (padded, Owen-scrambled Sobol;
// render/sobol.hpp). Both are counter-based.
enum class PathSampler : std::uint8_t { Independent, Sobol };
std::string_view sampler_name(PathSampler sampler);  // independent, sobol
std::optional<PathSampler> parse_sampler(std::string_view name);

struct PathOptions {
  std::uint32_t samples_per_pixel = kDefaultSamplesPerPixel;
  int max_bounces = kDefaultMaxBounces;
  PathSampler sampler = PathSampler::Independent;
  // --path-seed: XORed into both samplers' Philox keys, for independent
  // renders of one scene (0: the numbers of a render without it).
  std::uint32_t seed = 0;
};

}  // namespace nodetrace::tracer
