#include "nodetrace/tracer/render/pixel_order.hpp"

#include <algorithm>
#include <bit>

namespace nodetrace::tracer {

std::string_view pixel_order_name(PixelOrder order) {
  switch (order) {
    case PixelOrder::Scanline: return "scanline";
    case PixelOrder::Tiled: return "tiled";
    case PixelOrder::Morton: return "morton";
  }
  return "scanline";
}

std::optional<PixelOrder> parse_pixel_order(std::string_view name) {
  for (auto order : {PixelOrder::Scanline, PixelOrder::Tiled, PixelOrder::Morton}) {
    if (pixel_order_name(order) == name) return order;
  }
  return std::nullopt;
}

namespace {

// The even bits of a Morton code, compacted: one coordinate.
std::uint32_t morton_unpart(std::uint32_t x) {
  x &= 0x55555555;
  x = (x | (x >> 1)) & 0x33333333;
  x = (x | (x >> 2)) & 0x0F0F0F0F;
  x = (x | (x >> 4)) & 0x00FF00FF;
  x = (x | (x >> 8)) & 0x0000FFFF;
  return x;
}

}  // namespace

std::vector<std::uint32_t> pixel_sequence(int width, int height, PixelOrder order, int tile_size) {
  std::vector<std::uint32_t> sequence;
  if (width <= 0 || height <= 0) return sequence;
  sequence.reserve(static_cast<std::size_t>(width) * height);
  const auto index = [width](int x, int y) { return static_cast<std::uint32_t>(y * width + x); };
  switch (order) {
    case PixelOrder::Scanline:
      for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) sequence.push_back(index(x, y));
      break;
    case PixelOrder::Tiled: {
      const int t = std::max(1, tile_size);
      for (int ty = 0; ty < height; ty += t)
        for (int tx = 0; tx < width; tx += t)
          for (int y = ty; y < std::min(height, ty + t); ++y)
            for (int x = tx; x < std::min(width, tx + t); ++x) sequence.push_back(index(x, y));
      break;
    }
    case PixelOrder::Morton: {
      // Walk the Z-order curve of the enclosing power-of-two square and keep
      // the codes that fall inside the image.
      const auto side = std::bit_ceil(static_cast<std::uint32_t>(std::max(width, height)));
      const std::uint64_t codes = std::uint64_t{side} * side;
      for (std::uint64_t code = 0; code < codes; ++code) {
        const auto x = static_cast<int>(morton_unpart(static_cast<std::uint32_t>(code)));
        const auto y = static_cast<int>(morton_unpart(static_cast<std::uint32_t>(code >> 1)));
        if (x < width && y < height) sequence.push_back(index(x, y));
      }
      break;
    }
  }
  return sequence;
}

}  // namespace nodetrace::tracer
