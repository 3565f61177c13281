#include "nodetrace/tracer/row_sampling.hpp"

#include <algorithm>
#include <charconv>
#include <string>

#include "nodetrace/formats/error.hpp"

namespace nodetrace::tracer {

std::uint64_t parse_sample_rate(std::string_view text, std::string_view option) {
  const auto slash = text.find('/');
  std::uint64_t numerator = 0, every = 0;
  const auto whole = [](std::string_view digits, std::uint64_t& value) {
    const auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
    return !digits.empty() && error == std::errc() && end == digits.data() + digits.size();
  };
  if (slash == std::string_view::npos || !whole(text.substr(0, slash), numerator) ||
      !whole(text.substr(slash + 1), every) || numerator != 1 || every == 0) {
    throw formats::UsageError(std::string(option) + ": expected a rate 1/K with K a whole number of at least 1 "
                              "(1/1 renders everything), got '" + std::string(text) + "'");
  }
  return every;
}

std::uint64_t band_count(int height, std::uint32_t band_height) {
  if (height <= 0 || band_height == 0) return 0;
  return (std::uint64_t(height) + band_height - 1) / band_height;
}

namespace {

// SplitMix64's finaliser (Steele, Lea and Flood 2014): a well-mixed 64-bit
// hash, the same on every host.
std::uint64_t mix(std::uint64_t z) {
  z += 0x9E3779B97F4A7C15ull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

}  // namespace

std::vector<SampledBand> choose_bands(const RowSampling& sampling, std::uint64_t frame, int width, int height) {
  std::vector<SampledBand> chosen;
  const std::uint64_t bands = band_count(height, sampling.band_height);
  if (bands == 0 || width <= 0 || sampling.every == 0) return chosen;
  const std::uint64_t pixels = std::uint64_t(width) * std::uint64_t(height);
  const std::uint64_t band_pixels = std::uint64_t(width) * sampling.band_height;
  for (std::uint64_t stratum = 0; stratum * sampling.every < bands; ++stratum) {
    const std::uint64_t offset =
        sampling.every == 1 ? 0 : mix(mix(mix(sampling.seed) ^ frame) ^ stratum) % sampling.every;
    const std::uint64_t band = stratum * sampling.every + offset;
    if (band >= bands) continue;  // the last stratum is shorter: its band may fall off the end
    chosen.push_back({band, band * band_pixels, std::min(pixels, (band + 1) * band_pixels)});
  }
  return chosen;
}

bool band_rows(const RowSampling& sampling, PixelOrder order, int tile_size, int width, int height,
               const SampledBand& band, std::uint64_t& first_row, std::uint64_t& end_row) {
  const bool rows = order == PixelOrder::Scanline ||
                    (order == PixelOrder::Tiled && tile_size > 0 && sampling.band_height % tile_size == 0);
  if (!rows || width <= 0) return false;
  first_row = band.first_pixel / std::uint64_t(width);
  end_row = std::min<std::uint64_t>(std::uint64_t(height), band.end_pixel / std::uint64_t(width));
  return true;
}

}  // namespace nodetrace::tracer
