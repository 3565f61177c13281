// The order in which a render visits the pixels: the order of its records
// (docs/ARCHITECTURE.md "What a traversal fetches").
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

namespace nodetrace::tracer {

enum class PixelOrder : std::uint8_t { Scanline, Tiled, Morton };
std::string_view pixel_order_name(PixelOrder order);
std::optional<PixelOrder> parse_pixel_order(std::string_view name);

// Pixel indices (y * width + x) in the order they are rendered. Tiled: tiles
// of tile_size x tile_size in scanline order, scanline inside each. Morton:
// Z-order over the image.
std::vector<std::uint32_t> pixel_sequence(int width, int height, PixelOrder order, int tile_size);

}  // namespace nodetrace::tracer
