#include "nodetrace/tracer/render/trace_job.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <memory>

#include "nodetrace/base/error.hpp"
#include "nodetrace/base/split_level.hpp"
#include "nodetrace/formats/container/metadata.hpp"
#include "render/emitters.hpp"
#include "render/relocation.hpp"
#include "render/trace_header.hpp"
#include "render/trace_writer_sink.hpp"
#include "render/treelet_map.hpp"
#include "render/window_marker.hpp"

namespace nodetrace::tracer {

std::uint32_t layout_split_level_for(const LayoutTrace& trace, std::uint32_t node_size, const KdTreeStats& stats) {
  if (trace.layout != LayoutKind::Hybrid) return 0;
  if (trace.split_level) return *trace.split_level;
  if (trace.high_size) {
    return base::split_level_for_capacity(stats.nodes_per_level, base::LevelPlacement::contiguous_bytes(node_size),
                                          *trace.high_size);
  }
  throw base::UsageError("the hybrid layout needs --split-level K or --high-size SIZE");
}

namespace {

// A stream's addresses, base + i * size for i < count, must not wrap past
// 2^64 - 1: a wrapped address would alias the bottom of the address space.
void check_address_range(const char* option, std::uint64_t base, std::uint64_t count, std::uint64_t size,
                         const char* what) {
  if (count == 0) return;
  const std::uint64_t top = ~std::uint64_t{0};
  if (count > top / size || count * size - 1 > top - base) {
    throw base::UsageError(fmt::format("{} {:#x}: the {} {} of {} bytes would run past the 64-bit address "
                                          "space (the base can be at most {:#x})",
                                          option, base, count, what, size,
                                          count > top / size ? 0 : top - (count * size - 1)));
  }
}

// Checked before the scene is loaded: a hybrid layout needs its K; several
// traces of one render need a file each, and none can be standard output
// (it holds one stream).
void check_layout_traces(const std::vector<LayoutTrace>& targets, bool discard_records) {
  for (const auto& target : targets) {
    if (target.layout == LayoutKind::Hybrid && !target.split_level && !target.high_size) {
      throw base::UsageError("the hybrid layout needs --split-level K or --high-size SIZE");
    }
  }
  if (targets.size() == 1) return;
  if (discard_records) throw base::UsageError("--discard-records writes no trace: it takes one layout");
  // Several layouts and no file: their records go to other sinks only.
  if (std::all_of(targets.begin(), targets.end(), [](const LayoutTrace& target) { return target.output.empty(); })) {
    return;
  }
  std::vector<std::string> seen;
  for (const auto& target : targets) {
    if (target.output.empty() || target.output == "-") {
      throw base::UsageError("a render that writes several layouts needs a file name for each (not standard output)");
    }
    if (std::find(seen.begin(), seen.end(), target.output) != seen.end()) {
      throw base::UsageError(fmt::format("{}: two layouts would be written to the same file", target.output));
    }
    seen.push_back(target.output);
  }
}

// The path tracer's settings within their limits (integrator.hpp), and the
// images only it makes asked of it alone.
void check_path_options(const TraceJobOptions& options) {
  const RenderOptions& r = options.render;
  if (r.integrator != Integrator::Path) {
    if (!options.variance_pfm.empty()) throw base::UsageError("--variance-pfm needs --integrator path");
    if (r.environment) throw base::UsageError("--environment needs --integrator path");
    return;
  }
  if (r.path.samples_per_pixel < 1 || r.path.samples_per_pixel > kMaxSamplesPerPixel) {
    throw base::UsageError(fmt::format("--spp {}: expected 1 to {} samples per pixel", r.path.samples_per_pixel,
                                       kMaxSamplesPerPixel));
  }
  if (r.path.max_bounces < 0 || r.path.max_bounces > kMaxBounces) {
    throw base::UsageError(fmt::format("--max-bounces {}: expected 0 to {} bounce rays after the camera ray",
                                       r.path.max_bounces, kMaxBounces));
  }
  if (r.rays != RayScope::Whitted) {
    throw base::UsageError("--rays narrows the Whitted ray tree: --integrator path takes --max-bounces instead");
  }
}

bool is_black(const Vec3& colour) { return !(colour.x > 0) && !(colour.y > 0) && !(colour.z > 0); }

}  // namespace

TraceJobResult run_trace_job(const SceneSource& source, const TraceJobOptions& options,
                             const Renderer::Progress& progress) {
  const RenderOptions& r = options.render;
  if (r.width <= 0 || r.height <= 0) throw base::UsageError("width and height must be positive");
  if (r.max_depth < 1) throw base::UsageError("--max-depth must be at least 1");
  check_path_options(options);
  if (options.sampling && (options.sampling->every == 0 || options.sampling->band_height == 0)) {
    throw base::UsageError("--sample-rows and --band-height must be at least 1");
  }
  if (r.addresses.node_size == 0) throw base::UsageError("--node-size must be positive");
  if (!r.streams.nodes && !r.streams.lists && !r.streams.triangles) {
    throw base::UsageError("--streams selects no stream");
  }
  if (r.rays_in_flight > 1 || r.units > 1) {
    if (options.sampling) {
      throw base::UsageError("--sample-rows renders bands one at a time: it cannot be combined with "
                             "--rays-in-flight or --units above 1");
    }
    if (r.units > 1 && options.form == formats::RecordForm::Binary && !options.output.empty()) {
      throw base::UsageError("--units above 1: binary records have no tag field, so they cannot carry the unit");
    }
  }
  // The traces to write: the render's own layout first, then the others.
  std::vector<LayoutTrace> targets{{options.layout, options.split_level, options.high_size, options.output}};
  targets.insert(targets.end(), options.other_layouts.begin(), options.other_layouts.end());
  check_layout_traces(targets, options.discard_records);
  // Records are made when some layout has a sink (known for sure only once
  // the makers are asked, after the first tree is built).
  bool wants_records = !options.sink_makers.empty();
  for (const auto& target : targets) wants_records = wants_records || !target.output.empty();
  const Animation& animation = source.animation();
  std::vector<std::pair<std::uint64_t, double>> frames;
  if (options.time) {
    frames.emplace_back(options.frames.first, *options.time);
  } else {
    check_frame_range(options.frames, animation.frames, source.name());
    for (const auto f : options.frames.frames()) frames.emplace_back(f, animation.time_of_frame(f));
  }


  TraceJobResult result;
  // Each layout's sinks: its trace writer first (when it names a file), then
  // the caller's, in the order of options.sink_makers.
  std::vector<std::vector<std::unique_ptr<RecordSink>>> sinks(targets.size());
  bool any_sink = false;
  std::vector<formats::Record> relocated;  // a batch of records in another layout
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const auto [frame, time] = frames[i];
    const std::shared_ptr<const Scene> shared_scene = source.shared_at_time(time);
    const Scene& scene = *shared_scene;
    const AccelerationStructure tree =
        build_or_load(options.tree_cache, scene.triangles, options.accel, {options.build, options.bvh});
    AnimationFrameReport report;
    report.frame = frame;
    report.time = time;
    report.triangles = scene.triangles.size();
    report.tree = tree.stats();
    std::vector<std::uint32_t> split_levels;
    for (const auto& target : targets) {
      split_levels.push_back(layout_split_level_for(target, r.addresses.node_size, tree.stats()));
    }
    report.split_level = split_levels.front();
    report.other_split_levels.assign(split_levels.begin() + 1, split_levels.end());
    check_address_range("--node-base", r.addresses.node_base, tree.stats().nodes, r.addresses.node_size, "nodes");
    if (r.streams.lists) {
      check_address_range("--list-base", r.addresses.list_base, tree.stats().primitive_references,
                          r.addresses.list_entry_size, "list entries");
    }
    if (r.streams.triangles) {
      check_address_range("--triangle-base", r.addresses.triangle_base, scene.triangles.size(),
                          r.addresses.triangle_size, "triangles");
    }
    const std::uint32_t treelet_nodes = treelet_nodes_for(options.treelet_bytes, r.addresses.node_size);
    const Layout layout = make_layout(tree.shape(), options.layout, report.split_level, treelet_nodes);
    RenderOptions options_for_frame = r;
    // Records are made for the sinks, or for --discard-records to drop.
    options_for_frame.record = wants_records || options.discard_records;
    options_for_frame.animation_frame = frame;
    const Renderer renderer(scene, tree, layout, options_for_frame);

    if (i == 0) {
      result.plan = renderer.ray_plan();
      // The path tracer's light is the lights', the ambient term's and the
      // background's, or the environment map's in its place.
      const bool background_lights = r.environment ? r.environment->lights() : !is_black(scene.background);
      if (r.integrator == Integrator::Path && scene.lights.empty() && !background_lights &&
          is_black(scene.ambient) && detail::Emitters(scene).empty()) {
        result.notes.push_back(fmt::format("the scene has no light, no ambient light and {}: the path-traced image is "
                                           "black (the trace is whole)",
                                           r.environment ? "a black environment map" : "a black background"));
      }
      // Wider addresses only when some stream can reach past 32 bits.
      const std::uint64_t node_end =
          r.addresses.node_base + 4 * tree.stats().nodes * std::uint64_t{r.addresses.node_size};
      const bool wide = node_end > 0xFFFFFFFFull ||
                        (r.streams.lists && r.addresses.list_base > 0xC0000000ull) ||
                        (r.streams.triangles && r.addresses.triangle_base > 0xC0000000ull);
      formats::WriterOptions writer;
      writer.form = options.form;
      writer.threads = r.threads;
      writer.zstd_level = options.zstd_level;
      if (options.archive) formats::use_archive_setting(writer);
      writer.address_digits = wide ? 16 : 8;
      writer.units = r.units;
      for (std::size_t t = 0; t < targets.size(); ++t) {
        nlohmann::json header = make_trace_header(source, scene, options, targets[t], split_levels[t],
                                                  result.plan, frames.size(), tree.stats().depth_limit);
        if (!result.notes.empty()) header["render"]["notes"] = result.notes;
        if (t == 0) result.header = header;
        formats::WriterOptions layout_writer = writer;
        layout_writer.treelet_maps = targets[t].layout == LayoutKind::Treelet;
        const TraceStart start{t, targets[t], header, layout_writer};
        if (auto trace_writer = make_trace_writer_sink(start)) sinks[t].push_back(std::move(trace_writer));
        for (const auto& make_sink : options.sink_makers) {
          if (auto sink = make_sink(start)) sinks[t].push_back(std::move(sink));
        }
        any_sink = any_sink || !sinks[t].empty();
      }
    }
    // For each other layout with sinks: the address of the node in each slot
    // of `layout`; and each layout's treelet map (treelet layouts).
    std::vector<std::vector<std::uint64_t>> relocations(targets.size());
    std::vector<std::optional<formats::TreeletMap>> treelet_maps(targets.size());
    treelet_maps[0] = treelet_map_of(layout, r.addresses);
    for (std::size_t t = 1; t < targets.size(); ++t) {
      if (sinks[t].empty()) continue;
      const Layout other = make_layout(tree.shape(), targets[t].layout, split_levels[t], treelet_nodes);
      relocations[t] = relocation(layout, other, r.addresses);
      treelet_maps[t] = treelet_map_of(other, r.addresses);
    }
    for (std::size_t t = 0; t < targets.size(); ++t) {
      if (sinks[t].empty()) continue;
      formats::AnimationFrameMarker marker;
      marker.frame = frame;
      marker.time = time;
      marker.nodes_per_level = tree.stats().nodes_per_level;
      marker.nodes = tree.stats().nodes;
      marker.leaves = tree.stats().leaves;
      marker.depth = tree.stats().depth;
      marker.extra = {{"triangles", scene.triangles.size()},
                      {"empty_leaves", tree.stats().empty_leaves}};
      if (targets[t].layout == LayoutKind::Hybrid) marker.extra["split_level"] = split_levels[t];
      marker.treelets = std::move(treelet_maps[t]);
      for (const auto& sink : sinks[t]) sink->begin_animation_frame(marker);
    }
    Image image;
    const bool want_image = i == 0 && (!options.image.empty() || !options.pfm.empty() ||
                                       !options.variance_pfm.empty() || options.keep_image);
    const double done = double(i), count = double(frames.size());
    Renderer::Progress frame_progress;
    if (progress) frame_progress = [&](double f) { progress((done + f) / count); };
    Renderer::RecordCallback on_records;
    if (any_sink) {
      on_records = [&](std::span<const formats::Record> records) {
        for (const auto& sink : sinks.front()) sink->write(records);
        for (std::size_t t = 1; t < targets.size(); ++t) {
          if (sinks[t].empty()) continue;
          relocate(records, relocations[t], r.addresses, relocated);
          for (const auto& sink : sinks[t]) sink->write(relocated);
        }
      };
    }
    // --discard-records drops what it makes; so does a render whose makers all declined.
    if (options.discard_records || (options_for_frame.record && !any_sink)) {
      on_records = [](std::span<const formats::Record>) {};
    }
    if (options.sampling) {
      // Only the chosen bands are rendered; each begins a sample window.
      const std::vector<SampledBand> bands = choose_bands(*options.sampling, frame, r.width, r.height);
      report.bands_rendered = bands.size();
      std::vector<Renderer::PixelRun> runs;
      for (const auto& band : bands) runs.push_back({band.first_pixel, band.end_pixel});
      Renderer::RunStart begin_window;
      if (any_sink) {
        // An init-capture: clang's lambdas cannot capture the structured binding itself.
        begin_window = [&, frame_number = frame](std::size_t run) {
          const formats::WindowMarker marker = window_marker(options, bands[run], frame_number);
          for (const auto& layout_sinks : sinks) {
            for (const auto& sink : layout_sinks) sink->begin_window(marker);
          }
        };
      }
      report.render = renderer.render_runs(runs, begin_window, on_records, want_image ? &image : nullptr,
                                           frame_progress);
    } else {
      report.render = renderer.render(on_records, want_image ? &image : nullptr, frame_progress);
    }
    if (want_image) {
      if (!options.image.empty()) write_png(image, options.image);
      if (!options.pfm.empty()) write_pfm(image, image.pixels, options.pfm);
      if (!options.variance_pfm.empty()) write_pfm(image, image.variance, options.variance_pfm);
      if (options.keep_image) result.image = std::move(image);
    }
    result.total += report.render;
    result.total.seconds += report.render.seconds;
    result.frames.push_back(std::move(report));
  }
  nlohmann::json rays = nlohmann::json::object();
  for (const RayKind kind : result.plan.kinds) {
    rays[std::string(ray_kind_name(kind))] = result.total.rays[static_cast<int>(kind)];
  }
  nlohmann::json totals = {{"rays", rays},
                           {"node_fetches", result.total.node_fetches},
                           {"leaf_visits", result.total.leaf_visits},
                           {"triangle_tests", result.total.triangle_tests}};
  // Known only after rendering, so in the trailer (the header is written first).
  if (r.integrator == Integrator::Path) totals["nonfinite_samples"] = result.total.nonfinite_samples;
  for (const auto& layout_sinks : sinks) {
    for (const auto& sink : layout_sinks) sink->finish(totals);
  }
  return result;
}

}  // namespace nodetrace::tracer
