// The container header of a render's trace (FORMAT.md 2.1): only the inputs
// that change the records.
#pragma once

#include <cstdint>

#include <nlohmann/json.hpp>

#include "nodetrace/tracer/render/trace_job.hpp"

namespace nodetrace::tracer {

// The header of the trace of `target`, one of the job's layouts, whose first
// animation frame's scene is `first_scene` and whose tree's depth limit is
// `depth_limit`.
nlohmann::json make_trace_header(const SceneSource& source, const Scene& first_scene, const TraceJobOptions& options,
                                 const LayoutTrace& target, std::uint32_t split_level, const RayKindPlan& plan,
                                 std::uint64_t frame_count, int depth_limit);

}  // namespace nodetrace::tracer
