// The window marker a sampled band begins with.
#pragma once

#include <cstdint>

#include "nodetrace/formats/container/metadata.hpp"
#include "nodetrace/tracer/render/row_sampling.hpp"
#include "nodetrace/tracer/render/trace_job.hpp"

namespace nodetrace::tracer {

// The window marker of a sampled band: its number among the image's bands,
// its pixel-sequence positions, and its rows when it is whole rows.
formats::WindowMarker window_marker(const TraceJobOptions& options, const SampledBand& band, std::uint64_t frame);

}  // namespace nodetrace::tracer
