// The trace job: rendering a scene source for its records. For each
// animation frame it builds the acceleration structure (kd-tree or BVH),
// lays it out, renders, and feeds the frame's marker and records to the
// record sinks of every layout (record_sink.hpp): a trace writer for each
// layout given a file, and any sinks the caller adds.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "nodetrace/formats/record/record.hpp"
#include "nodetrace/tracer/render/animation_frame_range.hpp"
#include "nodetrace/tracer/render/layout_trace.hpp"
#include "nodetrace/tracer/render/record_sink.hpp"
#include "nodetrace/tracer/accel/acceleration_structure.hpp"
#include "nodetrace/tracer/accel/kdtree.hpp"
#include "nodetrace/tracer/accel/layout.hpp"
#include "nodetrace/tracer/accel/tree_cache.hpp"
#include "nodetrace/tracer/render/image.hpp"
#include "nodetrace/tracer/render/render.hpp"
#include "nodetrace/tracer/render/row_sampling.hpp"
#include "nodetrace/tracer/scene/scene.hpp"

namespace nodetrace::tracer {

struct TraceJobOptions {
  RenderOptions render;
  KdBuildOptions build;
  AccelKind accel = AccelKind::KdTree;
  BvhBuildOptions bvh;  // the BVHs' build
  // Built trees kept and loaded (--tree-cache); null: every tree is built.
  // Not owned; the records do not depend on it.
  const TreeCache* tree_cache = nullptr;
  LayoutKind layout = LayoutKind::Dfl;
  std::uint32_t treelet_bytes = kDefaultTreeletBytes;  // the treelet layout's budget
  // Hybrid K: a fixed level, or derived per frame from the high cache size.
  std::optional<std::uint32_t> split_level;
  std::optional<std::uint64_t> high_size;
  // Frames of the source's animation, or one instant `time` (numbered
  // frames.first).
  AnimationFrameRange frames;
  std::optional<double> time;
  // Render only sampled row bands (row_sampling.hpp); nullopt: every pixel.
  std::optional<RowSampling> sampling;
  std::string output;  // trace path, "-" for stdout; empty: no trace
  std::vector<LayoutTrace> other_layouts;  // further traces of the same render
  // Sinks beside the trace writers: each maker is asked once per layout.
  std::vector<RecordSinkMaker> sink_makers;
  bool discard_records = false;  // make the records but write none (benchmarks)
  formats::RecordForm form = formats::RecordForm::Din;
  int zstd_level = 3;  // compression level of the container's data frames
  bool archive = false;  // formats::use_archive_setting instead of zstd_level
  std::string image;  // PNG of the first frame; empty: none
  // PFM float images of the first frame: the pixels (path tracing: the mean
  // radiance) and, path tracing only, the per-pixel sample variance.
  std::string pfm, variance_pfm;
  // Keep the first frame's image in TraceJobResult::image (for callers that
  // use it in memory, such as the Python module).
  bool keep_image = false;
};

struct AnimationFrameReport {
  std::uint64_t frame = 0;
  double time = 0;
  std::uint64_t triangles = 0;
  KdTreeStats tree;  // the acceleration structure's figures
  std::uint32_t split_level = 0;
  std::vector<std::uint32_t> other_split_levels;  // of options.other_layouts, in order
  std::uint64_t bands_rendered = 0;  // sampled renders: the bands chosen in this frame
  RenderStats render;
};

struct TraceJobResult {
  std::vector<AnimationFrameReport> frames;
  RenderStats total;  // seconds: sum of the frames' render times
  nlohmann::json header;
  RayKindPlan plan;
  // What the render noticed and the front end should show (e.g. a path-traced
  // scene with no light and a black background is black).
  std::vector<std::string> notes;
  // The first frame's image when options.keep_image was set.
  std::optional<Image> image;
};

// The split level of a layout for a tree: the fixed one, or the one derived
// from the high cache size (hybrid only; 0 for the other layouts).
std::uint32_t layout_split_level_for(const LayoutTrace& trace, std::uint32_t node_size, const KdTreeStats& stats);

// Throws base::UsageError for options that cannot work, SceneError from the
// source, base::IoError / FormatError from the sinks. `progress` gets the
// fraction of all frames done.
TraceJobResult run_trace_job(const SceneSource& source, const TraceJobOptions& options,
                             const Renderer::Progress& progress = {});

}  // namespace nodetrace::tracer
