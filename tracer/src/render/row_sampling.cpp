#include "nodetrace/tracer/render/row_sampling.hpp"

#include <algorithm>
#include <string>

#include "nodetrace/base/sample_rate.hpp"

namespace nodetrace::tracer {

std::uint64_t band_count(int height, std::uint32_t band_height) {
  if (height <= 0 || band_height == 0) return 0;
  return (std::uint64_t(height) + band_height - 1) / band_height;
}


std::vector<SampledBand> choose_bands(const RowSampling& sampling, std::uint64_t frame, int width, int height) {
  std::vector<SampledBand> chosen;
  const std::uint64_t bands = band_count(height, sampling.band_height);
  if (bands == 0 || width <= 0 || sampling.every == 0) return chosen;
  const std::uint64_t pixels = std::uint64_t(width) * std::uint64_t(height);
  const std::uint64_t band_pixels = std::uint64_t(width) * sampling.band_height;
  for (std::uint64_t stratum = 0; stratum * sampling.every < bands; ++stratum) {
    const std::uint64_t offset =
        sampling.every == 1 ? 0 : base::mix64(base::mix64(base::mix64(sampling.seed) ^ frame) ^ stratum) % sampling.every;
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
