// Row-band sampling of a render (issue 8): the pixel sequence is cut into
// bands of band_height x width pixels; in each stratum of `every`
// consecutive bands one band is chosen by a seeded hash of (seed, animation
// frame, stratum), and only the chosen bands are rendered. Every band has
// the same chance 1/every of being chosen (a last, shorter stratum may
// give none), so a sum over the chosen bands times `every` estimates the
// full image's without bias.
//
// A band is a run of the pixel sequence, not a set of image rows: the
// records of a sampled trace are then stretches of the full trace, in the
// order one traversal unit issues them, which is what a cache simulated
// over the windows sees. In scanline order a band is band_height rows; in
// tiled order too when band_height is a multiple of the tile size; in
// Morton order it is a run of the Z-curve (a compact block of the image).
#pragma once

#include <cstdint>
#include <vector>

#include "nodetrace/tracer/render/pixel_order.hpp"

namespace nodetrace::tracer {

struct RowSampling {
  std::uint64_t every = 1;       // one band in every `every`
  std::uint32_t band_height = 1;  // rows per band (width pixels each)
  std::uint64_t seed = 0;
};


struct SampledBand {
  std::uint64_t band = 0;  // 0-based number among all bands of the image
  std::uint64_t first_pixel = 0, end_pixel = 0;  // positions [first, end) in the pixel sequence
};

// Bands in an image: ceil(height / band_height); the last may be shorter.
std::uint64_t band_count(int height, std::uint32_t band_height);

// The chosen bands of animation frame `frame`, in sequence order.
std::vector<SampledBand> choose_bands(const RowSampling& sampling, std::uint64_t frame, int width, int height);

// The image rows [first, end) a band covers when it is whole rows (scanline
// order; tiled with band_height a multiple of the tile size); false for a
// band that is not a set of rows.
bool band_rows(const RowSampling& sampling, PixelOrder order, int tile_size, int width, int height,
               const SampledBand& band, std::uint64_t& first_row, std::uint64_t& end_row);

}  // namespace nodetrace::tracer
