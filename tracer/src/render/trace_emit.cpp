#include "nodetrace/tracer/render/trace_emit.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cstdlib>
#include <memory>

#include "nodetrace/base/error.hpp"
#include "nodetrace/formats/container/metadata.hpp"
#include "nodetrace/base/split_level.hpp"
#include "nodetrace/formats/write/trace_writer.hpp"

namespace nodetrace::tracer {

namespace {

// A float as the double with the same shortest decimal form (0.2f -> 0.2, not
// 0.20000000298023224), so headers read as they were typed.
double shortest(float value) {
  char text[32];
  const auto [end, error] = std::to_chars(text, text + sizeof text, value);
  (void)error;
  return std::strtod(std::string(text, end).c_str(), nullptr);
}

nlohmann::json make_header(const SceneSource& source, const Scene& first_scene,
                           const TraceJobOptions& options, const LayoutTrace& target, std::uint32_t split_level,
                           const RayKindPlan& plan, std::uint64_t frame_count, int depth_limit) {
  const RenderOptions& r = options.render;
  nlohmann::json header;
  header["producer"] = {{"tool", "tracer"}, {"version", NODETRACE_VERSION}};
  header["scene"] = {{"name", source.name()},
                     {"hash", source.content_hash()},
                     {"triangles", first_scene.triangles.size()}};
  nlohmann::json render = {{"width", r.width},
                           {"height", r.height},
                           {"max_depth", r.max_depth},
                           {"pixel_order", pixel_order_name(r.pixel_order)},
                           {"frames", frame_count},
                           {"first_frame", options.frames.first}};
  if (options.frames.step != 1) render["frame_step"] = options.frames.step;
  if (r.pixel_order == PixelOrder::Tiled) render["tile_size"] = r.tile_size;
  if (options.time) render["time"] = *options.time;
  if (r.camera) {
    const Camera& c = *r.camera;
    render["camera"] = {{"eye", {shortest(c.eye.x), shortest(c.eye.y), shortest(c.eye.z)}},
                        {"look_at", {shortest(c.look_at.x), shortest(c.look_at.y), shortest(c.look_at.z)}},
                        {"up", {shortest(c.up.x), shortest(c.up.y), shortest(c.up.z)}},
                        {"fov", shortest(c.fov_y_degrees)}};
  }
  if (r.fov_y_degrees) render["fov"] = shortest(*r.fov_y_degrees);
  // Written only when narrowed, so a default render's header is as before.
  if (r.rays != RayScope::Whitted) render["rays"] = ray_scope_name(r.rays);
  if (r.first_light_only) render["lights"] = "first";
  // Written only with rays in flight, so a sequential render's header is as
  // before; the writer adds the top-level "units" the readers go by.
  if (r.rays_in_flight > 1 || r.units > 1) {
    render["rays_in_flight"] = r.rays_in_flight;
    render["units"] = r.units;
    render["unit_pixels"] = r.unit_pixels;
    render["ready_order"] = ready_order_name(r.ready_order);
  }
  header["render"] = render;
  nlohmann::json layout = {{"name", layout_name(target.layout)},
                           {"node_size", r.addresses.node_size},
                           {"node_base", r.addresses.node_base}};
  // Only the hybrid layout has a BFL top part: a split level written for the
  // others would make simulators compare their K against a meaningless 0.
  if (target.layout == LayoutKind::Hybrid) {
    layout["split_level"] = split_level;
    if (target.high_size) layout["high_size"] = *target.high_size;
  }
  if (target.layout == LayoutKind::Treelet) layout["treelet_bytes"] = options.treelet_bytes;
  header["layout"] = layout;
  if (options.accel == AccelKind::KdTree) {
    // No "accel" key: a kd-tree trace keeps the bytes it had before BVHs.
    header["kdtree"] = {{"traversal_cost", shortest(options.build.traversal_cost)},
                        {"intersection_cost", shortest(options.build.intersection_cost)},
                        {"empty_bonus", shortest(options.build.empty_bonus)},
                        {"max_depth", depth_limit}};
    // The default limit depends on each frame's triangle count: say so, since
    // max_depth is then the first frame's.
    if (options.build.max_depth == 0) header["kdtree"]["max_depth_default"] = "8 + 1.3 log2 triangles, per frame";
    if (options.build.leaf_size) header["kdtree"]["leaf_size"] = options.build.leaf_size;
  } else {
    const unsigned arity = accel_arity(options.accel);
    nlohmann::json accel = {{"name", accel_name(options.accel)},
                            {"arity", arity},
                            {"node_size", r.addresses.node_size},
                            {"stored_node_size", default_node_size(options.accel)},
                            {"record", "one per node fetched, the whole node, tagged with its level"}};
    accel["node"] = options.accel == AccelKind::CwBvh8
                        ? "8 child boxes quantized to 8 bits per plane on a power-of-two grid (conservative), "
                          "child references"
                        : fmt::format("{} full-precision child boxes and child references", arity);
    if (arity > 2) accel["collapse"] = "binary BVH opened greedily: the interior child of largest surface area first";
    header["accel"] = accel;
    header["bvh"] = {{"build", "binned SAH"},
                     {"bins", options.bvh.bins},
                     {"traversal_cost", shortest(options.bvh.traversal_cost)},
                     {"intersection_cost", shortest(options.bvh.intersection_cost)},
                     {"max_leaf_size", options.bvh.max_leaf_size}};
  }
  nlohmann::json cast = nlohmann::json::array();
  nlohmann::json left_out = nlohmann::json::object();
  for (int k = 0; k < kRayKindCount; ++k) {
    const std::string name(ray_kind_name(static_cast<RayKind>(k)));
    if (plan.cast[k]) {
      cast.push_back(name);
    } else {
      left_out[name] = plan.why_not[k];
    }
  }
  header["rays"] = {{"cast", cast}, {"left_out", left_out}};
  // A light behind the surface lights nothing there, so it gets no ray.
  if (plan.casts(RayKind::Shadow)) {
    header["rays"]["shadow"] = r.first_light_only ? "one to the first light when in front of the surface hit"
                                                  : "one per light in front of the surface hit";
  }
  nlohmann::json streams = nlohmann::json::array();
  if (r.streams.nodes) streams.push_back("nodes");
  if (r.streams.lists) streams.push_back("lists");
  if (r.streams.triangles) streams.push_back("triangles");
  header["streams"] = {{"kinds", streams}};
  if (r.streams.lists) {
    header["streams"]["list_base"] = r.addresses.list_base;
    header["streams"]["list_entry_size"] = r.addresses.list_entry_size;
  }
  if (r.streams.triangles) {
    header["streams"]["triangle_base"] = r.addresses.triangle_base;
    header["streams"]["triangle_size"] = r.addresses.triangle_size;
  }
  if (options.sampling) {
    const RowSampling& sampling = *options.sampling;
    formats::SamplingInfo info;
    info.method = "rows";
    info.every = sampling.every;
    info.band_height = sampling.band_height;
    info.seed = sampling.seed;
    info.bands = band_count(r.height, sampling.band_height);
    // A band is a run of band_height x width positions of the pixel sequence
    // (row_sampling.hpp): whole rows in scanline order.
    info.extra = {{"band_pixels", std::uint64_t(sampling.band_height) * std::uint64_t(r.width)}};
    header["sampling"] = info.to_json();
  }
  return header;
}

// The window marker of a sampled band: its number among the image's bands,
// its pixel-sequence positions, and its rows when it is whole rows.
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

}  // namespace

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

// The address, in layout `to`, of the node in each slot of layout `from`.
std::vector<std::uint64_t> relocation(const Layout& from, const Layout& to, const AddressMap& addresses) {
  std::vector<std::uint64_t> address_of_slot(from.slot_of_node.size());
  for (std::size_t node = 0; node < from.slot_of_node.size(); ++node) {
    address_of_slot[from.slot_of_node[node]] =
        addresses.node_base + std::uint64_t{to.slot_of_node[node]} * addresses.node_size;
  }
  return address_of_slot;
}

// `records` with each node fetch (a level tag) moved to its node's address in
// the other layout; the other streams do not depend on the layout.
void relocate(std::span<const formats::Record> records, const std::vector<std::uint64_t>& address_of_slot,
              const AddressMap& addresses, std::vector<formats::Record>& out) {
  out.assign(records.begin(), records.end());
  for (formats::Record& record : out) {
    if (!formats::is_level(record.tag)) continue;
    record.address = address_of_slot[(record.address - addresses.node_base) / addresses.node_size];
  }
}

}  // namespace

TraceJobResult run_trace_job(const SceneSource& source, const TraceJobOptions& options,
                             const Renderer::Progress& progress) {
  const RenderOptions& r = options.render;
  if (r.width <= 0 || r.height <= 0) throw base::UsageError("width and height must be positive");
  if (r.max_depth < 1) throw base::UsageError("--max-depth must be at least 1");
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
  const Animation& animation = source.animation();
  std::vector<std::pair<std::uint64_t, double>> frames;
  if (options.time) {
    frames.emplace_back(options.frames.first, *options.time);
  } else {
    check_frame_range(options.frames, animation.frames, source.name());
    for (const auto f : options.frames.frames()) frames.emplace_back(f, animation.time_of_frame(f));
  }


  TraceJobResult result;
  std::vector<std::unique_ptr<formats::TraceWriter>> writers(targets.size());
  std::vector<formats::Record> relocated;  // a batch of records in another layout
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const auto [frame, time] = frames[i];
    const Scene scene = source.at_time(time);
    const AccelerationStructure tree = AccelerationStructure::build(scene.triangles, options.accel,
                                                                   {options.build, options.bvh});
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
    // For each other trace: the address of the node in each slot of `layout`.
    std::vector<std::vector<std::uint64_t>> relocations;
    for (std::size_t t = 1; t < targets.size(); ++t) {
      relocations.push_back(relocation(
          layout, make_layout(tree.shape(), targets[t].layout, split_levels[t], treelet_nodes), r.addresses));
    }
    RenderOptions options_for_frame = r;
    // Records are made for a trace file, or for --discard-records to drop.
    options_for_frame.record = !options.output.empty() || options.discard_records;
    const Renderer renderer(scene, tree, layout, options_for_frame);

    if (i == 0) {
      result.plan = renderer.ray_plan();
      for (std::size_t t = 0; t < targets.size(); ++t) {
        nlohmann::json header = make_header(source, scene, options, targets[t], split_levels[t], result.plan,
                                            frames.size(), tree.stats().depth_limit);
        if (t == 0) result.header = header;
        if (targets[t].output.empty()) continue;
        formats::WriterOptions writer_options;
        writer_options.form = options.form;
        writer_options.threads = r.threads;
        writer_options.zstd_level = options.zstd_level;
        if (options.archive) formats::use_archive_setting(writer_options);
        // Wider addresses only when some stream can reach past 32 bits.
        const std::uint64_t node_end =
            r.addresses.node_base + 4 * tree.stats().nodes * std::uint64_t{r.addresses.node_size};
        const bool wide = node_end > 0xFFFFFFFFull ||
                          (r.streams.lists && r.addresses.list_base > 0xC0000000ull) ||
                          (r.streams.triangles && r.addresses.triangle_base > 0xC0000000ull);
        writer_options.address_digits = wide ? 16 : 8;
        writer_options.units = r.units;
        writers[t] = formats::TraceWriter::create(targets[t].output, header, writer_options);
      }
    }
    for (std::size_t t = 0; t < targets.size(); ++t) {
      if (!writers[t]) continue;
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
      writers[t]->begin_animation_frame(marker);
    }
    Image image;
    const bool want_image = i == 0 && !options.image.empty();
    const double done = double(i), count = double(frames.size());
    Renderer::Progress frame_progress;
    if (progress) frame_progress = [&](double f) { progress((done + f) / count); };
    Renderer::RecordSink sink;
    if (writers.front()) {
      sink = [&](std::span<const formats::Record> records) {
        writers.front()->write(records);
        for (std::size_t t = 1; t < targets.size(); ++t) {
          relocate(records, relocations[t - 1], r.addresses, relocated);
          writers[t]->write(relocated);
        }
      };
    }
    if (options.discard_records) sink = [](std::span<const formats::Record>) {};
    if (options.sampling) {
      // Only the chosen bands are rendered; each begins a sample window.
      const std::vector<SampledBand> bands = choose_bands(*options.sampling, frame, r.width, r.height);
      report.bands_rendered = bands.size();
      std::vector<Renderer::PixelRun> runs;
      for (const auto& band : bands) runs.push_back({band.first_pixel, band.end_pixel});
      Renderer::RunStart begin_window;
      if (writers.front()) {
        // An init-capture: clang's lambdas cannot capture the structured binding itself.
        begin_window = [&, frame_number = frame](std::size_t run) {
          const formats::WindowMarker marker = window_marker(options, bands[run], frame_number);
          for (const auto& writer : writers) writer->begin_window(marker);
        };
      }
      report.render = renderer.render_runs(runs, begin_window, sink, want_image ? &image : nullptr, frame_progress);
    } else {
      report.render = renderer.render(sink, want_image ? &image : nullptr, frame_progress);
    }
    if (want_image) write_png(image, options.image);
    result.total += report.render;
    result.total.seconds += report.render.seconds;
    result.frames.push_back(std::move(report));
  }
  nlohmann::json rays = nlohmann::json::object();
  for (int k = 0; k < kRayKindCount; ++k) {
    rays[std::string(ray_kind_name(static_cast<RayKind>(k)))] = result.total.rays[k];
  }
  for (const auto& writer : writers) {
    if (!writer) continue;
    writer->add_totals({{"rays", rays},
                        {"node_fetches", result.total.node_fetches},
                        {"leaf_visits", result.total.leaf_visits},
                        {"triangle_tests", result.total.triangle_tests}});
    writer->finish();
  }
  return result;
}

}  // namespace nodetrace::tracer
