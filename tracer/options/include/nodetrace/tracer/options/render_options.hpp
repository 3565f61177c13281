// Command-line options shared by `tracer render`, `tracer info` and the
// Python module's render(): frame selection, acceleration structure and its
// build, layout and render settings, and their parsing. A public header of
// the tracer's option layer (nodetrace_tracer_options), so that every front
// end takes the same names and values and gives the same errors.
#pragma once

#include <CLI/CLI.hpp>
#include <algorithm>
#include <fmt/format.h>

#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "nodetrace/base/byte_size.hpp"
#include "nodetrace/base/error.hpp"
#include "nodetrace/cli/number_range.hpp"
#include "nodetrace/cli/option_limits.hpp"
#include "nodetrace/base/sample_rate.hpp"
#include "nodetrace/tracer/scene/camera_checks.hpp"
#include "nodetrace/tracer/scene/scene_loader.hpp"
#include "nodetrace/tracer/render/trace_job.hpp"
#include "nodetrace/tracer/options/tree_cache_option.hpp"

namespace nodetrace::tracer::tools {

// Resource budgets of a render, stated in --help and in the errors.
// Image sides up to 16 bits; pixels up to 2^26 (8192x8192): the image and
// the pixel order take about 16 bytes a pixel, and pixel numbers are 32-bit.
inline constexpr int kMaxImageSide = 65535;
inline constexpr std::uint64_t kMaxImagePixels = std::uint64_t{1} << 26;
// Camera coordinates: beyond this a float ray origin has no precision left
// for a scene of ordinary size.
inline constexpr double kMaxCameraCoordinate = 1e15;
// Bytes per node: Dinero IV's sizes are 16 bits (an extended din size of
// 0x10000 or more is an error).
inline constexpr int kMaxNodeSize = 65535;

// Decimal, or hexadecimal with 0x.
inline std::uint64_t parse_address(const std::string& text, const std::string& option) {
  std::size_t used = 0;
  std::uint64_t value = 0;
  try {
    value = std::stoull(text, &used, 0);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || text.empty() || text[0] == '-') {
    throw base::UsageError(option + ": expected an address such as 4096 or 0x1000, got '" + text + "'");
  }
  return value;
}

inline StreamSelection parse_streams(const std::string& text) {
  StreamSelection s{false, false, false};
  std::size_t start = 0;
  while (start <= text.size()) {
    const auto comma = text.find(',', start);
    const std::string item = text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    if (item == "nodes") {
      s.nodes = true;
    } else if (item == "lists") {
      s.lists = true;
    } else if (item == "triangles") {
      s.triangles = true;
    } else {
      throw base::UsageError("--streams: unknown stream '" + item + "' (expected nodes, lists, triangles)");
    }
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return s;
}

struct SceneCommandOptions {
  std::optional<std::uint64_t> frame;
  std::optional<double> time;
  std::string frames;  // "A-B"
  float traversal_cost = KdBuildOptions{}.traversal_cost;
  float intersection_cost = KdBuildOptions{}.intersection_cost;
  float empty_bonus = KdBuildOptions{}.empty_bonus;
  int tree_depth = 0;
  std::uint32_t leaf_size = 0;
  std::string accel = "kdtree";
  float bvh_traversal_cost = BvhBuildOptions{}.traversal_cost;
  float bvh_intersection_cost = BvhBuildOptions{}.intersection_cost;
  std::uint32_t bvh_max_leaf_size = BvhBuildOptions{}.max_leaf_size;
  std::uint32_t bvh_bins = BvhBuildOptions{}.bins;
  std::optional<std::string> tree_cache;  // --tree-cache DIR (tree_cache_option.hpp)
  std::string default_lights = "key-fill";  // SceneLoadOptions::default_lights
};

inline SceneLoadOptions scene_load_options(const SceneCommandOptions& o, unsigned threads) {
  return {.threads = threads, .default_lights = o.default_lights != "none"};
}

// `frame_runs`: --frames (tracer render only: `tracer info` describes one frame).
inline void add_scene_options(CLI::App& app, SceneCommandOptions& o, bool frame_runs = true) {
  auto* frame = app.add_option("--frame", o.frame, "animation frame to render (default 0)");
  auto* time = app.add_option("--time", o.time, "scene time to render instead of a frame");
  frame->excludes(time);
  if (frame_runs) {
    auto* frames = app.add_option("--frames", o.frames,
                                  "a run of animation frames A-B, or every STEP-th of them A-B:STEP, one trace");
    frame->excludes(frames);
    time->excludes(frames);
  }
  app.add_option("--default-lights", o.default_lights,
                 "light a scene gets that its file does not give: key-fill (an OBJ file without light gets a "
                 "key and a fill point light and ambient 0.1, an AFF file without 'am' ambient 0.1; both said in a note and "
                 "the header) or none (neither: ambient 0)")
      ->check(CLI::IsMember({"key-fill", "none"}))
      ->capture_default_str();
  app.add_option("--traversal-cost", o.traversal_cost, "SAH cost of a traversal step")->capture_default_str();
  app.add_option("--intersection-cost", o.intersection_cost, "SAH cost of a triangle test")->capture_default_str();
  app.add_option("--empty-bonus", o.empty_bonus, "SAH bonus for cutting off empty space (0..1)")
      ->check(cli::NumberRange(0.0f, 1.0f))
      ->capture_default_str();
  app.add_option("--tree-depth", o.tree_depth, "deepest kd-tree level (default 8 + 1.3 log2 N)")
      ->check(cli::NumberRange(1, kMaxLevelLimit));
  app.add_option("--leaf-size", o.leaf_size,
                 "a node of at most N triangles is a leaf whatever the SAH says (default 0: the SAH decides)")
      ->check(cli::NumberRange(0u, 1000000u));
  app.add_option("--accel", o.accel,
                 "acceleration structure: kdtree (the paper's, 8-byte nodes), bvh2 (binary BVH, 64-byte nodes), "
                 "bvh4 / bvh8 (4- / 8-wide BVH collapsed from the binary one, 128- / 256-byte nodes of "
                 "full-precision boxes), cwbvh8 (8-wide, 80-byte nodes of quantized boxes)")
      ->check(CLI::IsMember({"kdtree", "bvh2", "bvh4", "bvh8", "cwbvh8"}))
      ->capture_default_str();
  app.add_option("--bvh-traversal-cost", o.bvh_traversal_cost, "BVH SAH cost of visiting a node")
      ->capture_default_str();
  app.add_option("--bvh-intersection-cost", o.bvh_intersection_cost, "BVH SAH cost of a triangle test")
      ->capture_default_str();
  app.add_option("--bvh-max-leaf-size", o.bvh_max_leaf_size,
                 "BVH: a node of more triangles is always split; up to this many become a leaf when the SAH "
                 "says a leaf is cheaper")
      ->check(cli::NumberRange(1u, 1000000u))
      ->capture_default_str();
  app.add_option("--bvh-bins", o.bvh_bins, "BVH: SAH bins per axis (bins - 1 candidate planes)")
      ->check(cli::NumberRange(2u, 256u))
      ->capture_default_str();
  add_tree_cache_option(app, o.tree_cache);
}

// A tree build's two SAH costs: finite and positive.
inline void check_sah_costs(float traversal, float intersection, const std::string& prefix) {
  cli::check_finite(traversal, prefix + "traversal-cost");
  cli::check_finite(intersection, prefix + "intersection-cost");
  if (!(traversal > 0) || !(intersection > 0)) {
    throw base::UsageError(prefix + "traversal-cost and " + prefix + "intersection-cost must be positive");
  }
}

inline BvhBuildOptions make_bvh_options(const SceneCommandOptions& s) {
  check_sah_costs(s.bvh_traversal_cost, s.bvh_intersection_cost, "--bvh-");
  return {s.bvh_traversal_cost, s.bvh_intersection_cost, s.bvh_max_leaf_size, s.bvh_bins};
}

// Rows per sampled band by default: one. Measured on BART Robot frame 0 at
// 800x600 (hybrid layout for 8 KB, --sample-rows 1/16, seeds 1-6, cachesim
// single and split at 4/8/16 KB): the mean absolute error of the miss ratios
// was 0.07 points with bands of 1 row, 0.12 with 2, 0.26 with 4, 0.22 with
// 8, 0.93 with 16 and 2.5 with 32, at the same render time: thinner bands
// make more, finer strata.
inline constexpr std::uint32_t kDefaultBandHeight = 1;

struct RenderCommandOptions {
  int width = 800, height = 600, max_depth = 10, tile_size = 8;
  std::string pixel_order = "scanline";
  std::vector<double> eye, look_at, up;
  std::optional<double> fov;
  unsigned threads = 0;
  std::vector<std::string> layouts;
  std::vector<std::uint32_t> split_levels;
  std::vector<std::string> high_sizes;
  std::string node_base = "0", list_base, triangle_base;
  std::optional<std::uint32_t> node_size;  // default: the acceleration structure's
  std::uint32_t treelet_bytes = kDefaultTreeletBytes;
  std::string sample_rows;
  std::uint32_t band_height = kDefaultBandHeight;
  std::uint64_t sample_seed = 0;
  std::string rays = "whitted", lights = "all";
  unsigned rays_in_flight = 1, units = 1, unit_pixels = 64;
  std::string ready_order = "depth-first";
  // Path tracing: --integrator and the options only it takes.
  std::string integrator = "whitted";
  std::optional<std::uint32_t> spp;
  std::optional<int> max_bounces;
  std::optional<std::string> sampler;
  std::optional<std::uint32_t> path_seed;
  std::optional<std::string> environment;  // --environment FILE.pfm
};

// Ray slots per traversal unit at most: a step then issues up to 4096
// fetches per unit.
inline constexpr unsigned kMaxRaysInFlight = 4096;

// --integrator and the path tracer's options (integrator.hpp states the
// defaults and limits, and why).
inline void add_path_options(CLI::App& app, RenderCommandOptions& o) {
  app.add_option("--integrator", o.integrator,
                 "whitted (the paper's ray tree) or path (a path tracer: random bounces, next-event estimation "
                 "toward the lights, the background as environment light)")
      ->check(CLI::IsMember({"whitted", "path"}))
      ->capture_default_str();
  app.add_option("--spp", o.spp,
                 fmt::format("--integrator path: samples per pixel, 1 to {} (default {}: the smallest workload)",
                             kMaxSamplesPerPixel, kDefaultSamplesPerPixel))
      ->check(cli::NumberRange(1u, kMaxSamplesPerPixel));
  app.add_option("--max-bounces", o.max_bounces,
                 fmt::format("--integrator path: bounce rays after the camera ray, 0 to {} (default {}; Russian "
                             "roulette from bounce {})",
                             kMaxBounces, kDefaultMaxBounces, kRouletteFromBounce))
      ->check(cli::NumberRange(0, kMaxBounces));
  app.add_option("--sampler", o.sampler,
                 "--integrator path: where the uniform numbers come from: independent (Philox, the default) or "
                 "sobol (Owen-scrambled Sobol: lower error at the same samples); both give the same bytes for "
                 "any threads, pixel order or rays in flight")
      ->check(CLI::IsMember({"independent", "sobol"}));
  app.add_option("--path-seed", o.path_seed,
                 "--integrator path: another set of random numbers for either sampler, for independent renders "
                 "of one scene (default 0: the numbers of a render without it)")
      ->type_name("UINT");
  app.add_option("--environment", o.environment,
                 "--integrator path: light from an equirectangular colour PFM map of linear radiance instead of the "
                 "background, oriented as Blender's environment texture (+Z up, +X the middle column), sampled by "
                 "luminance for next-event estimation")
      ->type_name("FILE.pfm");
}

// One rule for tracer render and tracer info: --max-depth is the Whitted
// tracer's ray depth, --max-bounces the path tracer's; each is refused with
// the other integrator rather than ignored.
inline void check_depth_options(const std::string& integrator, bool max_depth_given, bool max_bounces_given) {
  const bool path = *parse_integrator(integrator) == Integrator::Path;
  if (path && max_depth_given) {
    throw base::UsageError("--max-depth is the Whitted tracer's ray depth: --integrator path takes --max-bounces");
  }
  if (!path && max_bounces_given) {
    throw base::UsageError("--max-bounces needs --integrator path (Whitted: --max-depth)");
  }
}

// The path tracer's settings; its options without --integrator path are
// refused (--max-bounces by check_depth_options).
inline void apply_integrator(const RenderCommandOptions& r, RenderOptions& render) {
  render.integrator = *parse_integrator(r.integrator);
  if (render.integrator != Integrator::Path) {
    if (r.spp) throw base::UsageError("--spp needs --integrator path (the Whitted tracer casts one ray per pixel)");
    if (r.sampler) throw base::UsageError("--sampler needs --integrator path (the Whitted tracer draws no numbers)");
    if (r.path_seed) {
      throw base::UsageError("--path-seed needs --integrator path (the Whitted tracer draws no numbers)");
    }
    if (r.environment) {
      throw base::UsageError("--environment needs --integrator path (the Whitted tracer shows the background colour)");
    }
    return;
  }
  if (r.sampler) render.path.sampler = *parse_sampler(*r.sampler);
  render.path.seed = r.path_seed.value_or(0);
  render.path.samples_per_pixel = r.spp.value_or(kDefaultSamplesPerPixel);
  render.path.max_bounces = r.max_bounces.value_or(kDefaultMaxBounces);
}

inline void add_render_options(CLI::App& app, RenderCommandOptions& o) {
  app.add_option("--width", o.width, "image width (at most 65535; width x height at most 2^26 pixels)")
      ->check(cli::NumberRange(1, kMaxImageSide))
      ->capture_default_str();
  app.add_option("--height", o.height, "image height (at most 65535)")
      ->check(cli::NumberRange(1, kMaxImageSide))
      ->capture_default_str();
  app.add_option("--max-depth", o.max_depth, "ray tree depth (primary rays are depth 1)")
      ->check(cli::NumberRange(1, 64))
      ->capture_default_str();
  app.add_option("--rays", o.rays,
                 "rays traced: primary, primary+shadow (no reflection or refraction) or whitted (all)")
      ->check(CLI::IsMember({"primary", "primary+shadow", "whitted"}))
      ->capture_default_str();
  app.add_option("--lights", o.lights, "lights that get shadow rays: all, or the scene's first only")
      ->check(CLI::IsMember({"all", "first"}))
      ->capture_default_str();
  app.add_option("--pixel-order", o.pixel_order, "scanline, tiled or morton")
      ->check(CLI::IsMember({"scanline", "tiled", "morton"}))
      ->capture_default_str();
  app.add_option("--tile-size", o.tile_size, "tile side for --pixel-order tiled")
      ->check(cli::NumberRange(1, kMaxImageSide))
      ->capture_default_str();
  app.add_option("--eye", o.eye, "camera position X Y Z")->expected(3);
  app.add_option("--look-at", o.look_at, "point the camera looks at X Y Z")->expected(3);
  app.add_option("--up", o.up, "camera up direction X Y Z")->expected(3);
  app.add_option("--fov", o.fov, "vertical field of view in degrees, 0.01 to 179");
  app.add_option("--threads", o.threads,
                 "threads reading an OBJ scene, rendering and building the kd-tree (default: one per core; at most 16 per core); the output does not depend on it");
  app.add_option("--layout", o.layouts,
                 "tree layout: dfl, bfl, hybrid, veb or treelet, or several, comma-separated, for one trace "
                 "each from one render (-o with {layout}) (default: hybrid when --split-level or --high-size "
                 "is given, else dfl)")
      ->delimiter(',')
      ->check(CLI::IsMember({"dfl", "bfl", "hybrid", "veb", "treelet"}));
  app.add_option("--treelet-bytes", o.treelet_bytes,
                 "treelet layout: bytes per treelet (as many whole nodes as fit, at least one); treelets grow "
                 "from their root by the child of largest surface area")
      ->check(cli::NumberRange(1u, 1u << 30))
      ->capture_default_str();
  app.add_option("--split-level", o.split_levels,
                 "hybrid layout: levels < K in BFL; several K, comma-separated: one trace each")
      ->delimiter(',')
      ->check(cli::NumberRange(0, kMaxLevelLimit));
  app.add_option("--high-size", o.high_sizes,
                 "hybrid layout: K = the most levels whose nodes fit a high-level cache of SIZE bytes "
                 "(e.g. 4k); several sizes, comma-separated: one trace each (with --split-level: one trace "
                 "per K and per size)")
      ->delimiter(',');
  app.add_option("--node-base", o.node_base, "address of layout slot 0")->capture_default_str();
  app.add_option("--list-base", o.list_base, "address of the leaf primitive lists (--streams lists; default 0x40000000)");
  app.add_option("--triangle-base", o.triangle_base, "address of the triangles (--streams triangles; default 0x80000000)");
  app.add_option("--node-size", o.node_size,
                 "bytes per node, for what-if studies (at most 65535; default: the structure's: kdtree 8, "
                 "bvh2 64, bvh4 128, bvh8 256, cwbvh8 80)")
      ->check(cli::NumberRange(1, kMaxNodeSize));
  auto* rows = app.add_option("--sample-rows", o.sample_rows,
                              "render one band of rows in every K (rate 1/K), the other bands' rays never traced; "
                              "each band begins a sample window of the trace (with --pixel-order tiled or morton "
                              "a band is the same number of pixels, a run of that order)");
  app.add_option("--band-height", o.band_height,
                 "--sample-rows: rows per band; 1 measured best (BART Robot 800x600 at 1/16: miss-ratio "
                 "error 0.07 points with 1 row, 0.26 with 4, 0.93 with 16, at the same time)")
      ->check(cli::NumberRange(1, kMaxImageSide))
      ->needs(rows)
      ->capture_default_str();
  app.add_option("--rays-in-flight", o.rays_in_flight,
                 "ray slots per traversal unit: each step every busy slot issues its ray's next node fetch, in "
                 "slot order; 1 is one ray at a time (docs/guide/rays-in-flight.md)")
      ->check(cli::NumberRange(1u, kMaxRaysInFlight))
      ->capture_default_str();
  app.add_option("--units", o.units,
                 "traversal units, their fetches merged by step (unit 0's, unit 1's, ...); above 1 each record "
                 "carries its unit after the tag")
      ->check(cli::NumberRange(1u, formats::kMaxUnits))
      ->capture_default_str();
  app.add_option("--unit-pixels", o.unit_pixels,
                 "pixels are dealt to the units in runs of this many positions of the pixel order, run r to "
                 "unit r mod units (64: one 8x8 tile of --pixel-order tiled)")
      ->check(cli::NumberRange(1u, 1u << 26))
      ->capture_default_str();
  app.add_option("--ready-order", o.ready_order,
                 "where a finished ray's secondary rays join its unit's queue, always ahead of the next primary "
                 "ray: depth-first (at the front: a pixel's rays stay together; one slot is the sequential "
                 "order) or breadth-first (behind the secondary rays waiting)")
      ->check(CLI::IsMember({"depth-first", "breadth-first"}))
      ->capture_default_str();
  add_path_options(app, o);
  app.add_option("--sample-seed", o.sample_seed,
                 "--sample-rows: seed of the band chosen in each run of K bands (same seed: same bands)")
      ->needs(rows)
      ->capture_default_str();
}

inline KdBuildOptions make_build_options(const SceneCommandOptions& s) {
  check_sah_costs(s.traversal_cost, s.intersection_cost, "--");
  if (!(s.empty_bonus >= 0 && s.empty_bonus <= 1)) {
    throw base::UsageError(fmt::format("--empty-bonus {}: expected a number from 0 to 1", s.empty_bonus));
  }
  KdBuildOptions build;
  build.traversal_cost = s.traversal_cost;
  build.intersection_cost = s.intersection_cost;
  build.empty_bonus = s.empty_bonus;
  build.max_depth = s.tree_depth;
  build.leaf_size = s.leaf_size;
  return build;
}

// Frame range from --frame / --time / --frames into the job options.
inline void apply_frames(const SceneCommandOptions& s, TraceJobOptions& options) {
  if (s.frame) options.frames = {*s.frame, *s.frame, 1};
  if (s.time) options.time = cli::check_finite(*s.time, "--time");
  if (!s.frames.empty()) options.frames = parse_frame_range(s.frames, "--frames");
}

// A point or direction option: finite, and within kMaxCameraCoordinate.
inline Vec3 camera_vector(const std::vector<double>& v, const char* option) {
  const std::string given = fmt::format("{} {:g} {:g} {:g}", option, v[0], v[1], v[2]);
  for (const double x : v) {
    if (!std::isfinite(x)) throw base::UsageError(given + ": expected finite numbers");
    if (std::fabs(x) > kMaxCameraCoordinate) {
      throw base::UsageError(fmt::format("{}: expected coordinates of at most {:g} in magnitude", given,
                                            kMaxCameraCoordinate));
    }
  }
  return {static_cast<float>(v[0]), static_cast<float>(v[1]), static_cast<float>(v[2])};
}

inline void check_image_size(int width, int height) {
  const std::uint64_t pixels = std::uint64_t(width) * std::uint64_t(height);
  if (pixels > kMaxImagePixels) {
    throw base::UsageError(fmt::format("--width {} --height {}: at most {} pixels (e.g. 8192x8192)", width,
                                          height, kMaxImagePixels));
  }
}

// A layout the options ask for, and its name in an output pattern's
// {layout}: dfl, bfl, veb, treelet, hybrid-4k (--high-size as typed), hybrid-k6.
struct LayoutChoice {
  LayoutTrace trace;
  std::string name;
};

// Every layout of --layout, the hybrid once per --split-level or --high-size
// value, in the order given.
inline std::vector<LayoutChoice> layout_choices(const RenderCommandOptions& r) {
  std::vector<std::string> layouts = r.layouts;
  if (layouts.empty()) layouts.push_back(r.split_levels.empty() && r.high_sizes.empty() ? "dfl" : "hybrid");
  const bool any_hybrid = std::find(layouts.begin(), layouts.end(), "hybrid") != layouts.end();
  if (!any_hybrid && (!r.split_levels.empty() || !r.high_sizes.empty())) {
    throw base::UsageError("--split-level and --high-size apply to --layout hybrid only");
  }
  std::vector<LayoutChoice> choices;
  for (const auto& name : layouts) {
    LayoutTrace trace;
    trace.layout = *parse_layout_name(name);
    if (trace.layout != LayoutKind::Hybrid) {
      choices.push_back({trace, name});
      continue;
    }
    // Without K or a size the trace job says what the hybrid layout needs.
    if (r.split_levels.empty() && r.high_sizes.empty()) choices.push_back({trace, name});
    for (const std::uint32_t k : r.split_levels) {
      trace.split_level = k;
      choices.push_back({trace, fmt::format("hybrid-k{}", k)});
    }
    trace.split_level.reset();
    for (const auto& size : r.high_sizes) {
      trace.high_size = base::parse_byte_size(size, "--high-size");
      choices.push_back({trace, "hybrid-" + size});
    }
  }
  return choices;
}

// An output pattern's file for each layout: {layout} replaced by the
// layout's name; a pattern without it names one layout's file. `optional`:
// no pattern is no file for any layout.
inline std::vector<std::string> layout_files(const std::vector<LayoutChoice>& choices, const std::string& pattern,
                                             const char* option, bool optional = false) {
  constexpr std::string_view kPlaceholder = "{layout}";
  const auto place = pattern.find(kPlaceholder);
  if (choices.size() > 1 && place == std::string::npos && !(optional && pattern.empty())) {
    throw base::UsageError(fmt::format("{} layouts: {} needs {{layout}} in the file name, which each layout's name "
                                       "replaces (e.g. {} out/{{layout}}{})",
                                       choices.size(), option, option,
                                       std::string_view(option) == "-o" ? ".din.zst" : ".json"));
  }
  std::vector<std::string> files;
  for (const auto& choice : choices) {
    files.push_back(pattern);
    if (place != std::string::npos) files.back().replace(place, kPlaceholder.size(), choice.name);
  }
  return files;
}

// -o's {layout} replaced by each layout's name: one trace per layout.
// `traces_optional`: no -o was given, or the records go elsewhere too
// (--simulate), so several layouts need no {layout} in an empty -o.
inline void assign_outputs(TraceJobOptions& options, const std::vector<LayoutChoice>& choices, const std::string& output,
                           bool traces_optional) {
  const std::vector<std::string> files = layout_files(choices, output, "-o", traces_optional);
  options.output = files.front();
  for (std::size_t i = 1; i < choices.size(); ++i) options.other_layouts[i - 1].output = files[i];
}

// `output`: -o as given, a pattern with {layout} for several layouts.
inline TraceJobOptions make_job_options(const RenderCommandOptions& r, const SceneCommandOptions& s,
                                        const std::string& output, bool traces_optional = false) {
  check_image_size(r.width, r.height);
  TraceJobOptions options;
  options.build = make_build_options(s);
  options.accel = *parse_accel_name(s.accel);
  options.bvh = make_bvh_options(s);
  options.treelet_bytes = r.treelet_bytes;
  apply_frames(s, options);
  RenderOptions& render = options.render;
  render.width = r.width;
  render.height = r.height;
  render.max_depth = r.max_depth;
  render.rays = r.rays == "primary"          ? RayScope::Primary
                : r.rays == "primary+shadow" ? RayScope::PrimaryShadow
                                             : RayScope::Whitted;
  render.first_light_only = r.lights == "first";
  apply_integrator(r, render);
  render.pixel_order = *parse_pixel_order(r.pixel_order);
  render.tile_size = r.tile_size;
  render.rays_in_flight = r.rays_in_flight;
  render.units = r.units;
  render.unit_pixels = r.unit_pixels;
  render.ready_order = *parse_ready_order(r.ready_order);
  render.threads = cli::check_thread_count(r.threads, "--threads");
  options.build.threads = render.threads;
  render.addresses.node_size = r.node_size.value_or(default_node_size(options.accel));
  render.addresses.node_base = parse_address(r.node_base, "--node-base");
  if (!r.list_base.empty()) render.addresses.list_base = parse_address(r.list_base, "--list-base");
  if (!r.triangle_base.empty()) {
    render.addresses.triangle_base = parse_address(r.triangle_base, "--triangle-base");
  }
  if (r.fov) {
    if (!(*r.fov >= 0.01 && *r.fov <= 179)) {
      throw base::UsageError(fmt::format("--fov {}: expected degrees from 0.01 to 179", *r.fov));
    }
    render.fov_y_degrees = static_cast<float>(*r.fov);
  }
  if (!r.eye.empty() || !r.look_at.empty() || !r.up.empty()) {
    if (r.eye.empty() || r.look_at.empty()) {
      throw base::UsageError("a camera needs both --eye and --look-at (--up and --fov are optional)");
    }
    Camera camera;
    camera.eye = camera_vector(r.eye, "--eye");
    camera.look_at = camera_vector(r.look_at, "--look-at");
    if (!r.up.empty()) camera.up = camera_vector(r.up, "--up");
    switch (camera_problem(camera.eye, camera.look_at, camera.up)) {
      case CameraProblem::EyeAtLookAt:
        throw base::UsageError("--eye and --look-at are the same point: the camera looks nowhere");
      case CameraProblem::UpAlongView:
        throw base::UsageError(fmt::format("--up is parallel to the view direction (up {:g} {:g} {:g}{}): "
                                              "expected a direction across the view",
                                              camera.up.x, camera.up.y, camera.up.z,
                                              r.up.empty() ? ", the default" : ""));
      case CameraProblem::None: break;
    }
    render.camera = camera;
  }
  if (!r.sample_rows.empty()) {
    options.sampling = RowSampling{base::parse_sample_rate(r.sample_rows, "--sample-rows"), r.band_height, r.sample_seed};
  }
  const std::vector<LayoutChoice> choices = layout_choices(r);
  options.layout = choices.front().trace.layout;
  options.split_level = choices.front().trace.split_level;
  options.high_size = choices.front().trace.high_size;
  for (std::size_t i = 1; i < choices.size(); ++i) options.other_layouts.push_back(choices[i].trace);
  assign_outputs(options, choices, output, traces_optional);
  return options;
}

}  // namespace nodetrace::tracer::tools
