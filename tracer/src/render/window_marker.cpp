#include "render/window_marker.hpp"

namespace nodetrace::tracer {

formats::WindowMarker window_marker(const TraceJobOptions& options, const SampledBand& band, std::uint64_t frame) {
  const RenderOptions& r = options.render;
  formats::WindowMarker marker;
  marker.window = band.band;
  marker.frame = frame;
  marker.extra = {{"pixels", {band.first_pixel, band.end_pixel}}};
  std::uint64_t first_row = 0, end_row = 0;
  if (band_rows(*options.sampling, r.pixel_order, r.tile_size, r.width, r.height, band, first_row, end_row)) {
    marker.extra["rows"] = {first_row, end_row};
  }
  return marker;
}

}  // namespace nodetrace::tracer
