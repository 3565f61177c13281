// tracer info SCENE: what a scene holds, its acceleration structure, and which ray kinds a
// render of it casts.
#include <CLI/CLI.hpp>
#include <fmt/core.h>
#include <fmt/ranges.h>

#include <sys/resource.h>

#include <cstdio>
#include <map>
#include <new>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "nodetrace/cli/command_line.hpp"
#include "nodetrace/cli/number_range.hpp"
#include "nodetrace/cli/csv_text.hpp"
#include "nodetrace/cli/format_option.hpp"
#include "nodetrace/cli/exit_status.hpp"
#include "nodetrace/base/error.hpp"
#include "nodetrace/base/split_level.hpp"
#include "nodetrace/tracer/scene/scene_loader.hpp"
#include "nodetrace/tracer/options/render_options.hpp"

namespace nodetrace::tracer::tools {

namespace {

// The options of `tracer info` and what it does with them.
struct InfoCommand {
  std::string scene_spec, format = "table";
  int max_depth = 10;
  std::string integrator = "whitted";
  std::optional<int> max_bounces;
  std::optional<std::string> environment;
  CLI::Option* max_depth_option = nullptr;
  unsigned threads = 0;
  std::optional<std::uint32_t> node_size_option;  // default: the acceleration structure's
  SceneCommandOptions scene_options;

  void add_options(CLI::App& app);
  int run() const;
};

void InfoCommand::add_options(CLI::App& app) {
  app.add_option("scene", scene_spec, "an .obj or .aff file, or a built-in scene's name")->required();
  cli::add_format_option(app, format, "json: one object, csv: one table field,value");
  max_depth_option = app.add_option("--max-depth", max_depth, "ray tree depth assumed for the ray kinds")
      ->check(cli::NumberRange(1, 64))
      ->capture_default_str();
  app.add_option("--integrator", integrator, "whitted or path: whose ray kinds to show")
      ->check(CLI::IsMember({"whitted", "path"}))
      ->capture_default_str();
  app.add_option("--max-bounces", max_bounces,
                 fmt::format("--integrator path: bounce rays after the camera ray assumed for the ray kinds, 0 to {} "
                             "(default {})",
                             kMaxBounces, kDefaultMaxBounces))
      ->check(cli::NumberRange(0, kMaxBounces));
  app.add_option("--environment", environment,
                 "--integrator path: the environment map assumed to light the scene (as tracer render's), for the "
                 "ray kinds")
      ->type_name("FILE.pfm");
  app.add_option("--node-size", node_size_option,
                 "bytes per node, for the bytes and split levels shown (at most 65535; default: the structure's)")
      ->check(cli::NumberRange(1, kMaxNodeSize));
  app.add_option("--threads", threads, "threads reading an OBJ file and building the kd-tree (default: one per core); neither depends on it");
  add_scene_options(app, scene_options, /*frame_runs=*/false);
}

int InfoCommand::run() const {
  return cli::exit_status_of("tracer info", [&] {
    // Options first, before a scene is loaded.
    if (scene_options.time) cli::check_finite(*scene_options.time, "--time");
    KdBuildOptions build_options = make_build_options(scene_options);
    check_depth_options(integrator, max_depth_option->count() != 0, max_bounces.has_value());
    const bool path = *parse_integrator(integrator) == Integrator::Path;
    if (environment && !path) throw base::UsageError("--environment needs --integrator path");
    // Read before the scene: a bad map is refused as tracer render refuses it.
    const bool environment_light = environment && load_environment_map(*environment)->lights();
    build_options.threads = cli::check_thread_count(threads, "--threads");
    const auto source = open_scene(scene_spec, scene_load_options(scene_options, build_options.threads));
    for (const auto& warning : source->warnings()) std::fprintf(stderr, "tracer info: warning: %s\n", warning.c_str());
    const Animation& animation = source->animation();
    const std::uint64_t frame = scene_options.frame.value_or(0);
    if (!scene_options.time) check_frame_range({frame, frame, 1}, animation.frames, source->name());
    const double time = scene_options.time.value_or(animation.time_of_frame(frame));
    const std::shared_ptr<const Scene> shared_scene = source->shared_at_time(time);
    const Scene& scene = *shared_scene;
    const AccelKind kind = *parse_accel_name(scene_options.accel);
    const std::unique_ptr<TreeCache> tree_cache = open_tree_cache(scene_options.tree_cache, "tracer info");
    const AccelerationStructure tree =
        build_or_load(tree_cache.get(), scene.triangles, kind, {build_options, make_bvh_options(scene_options)});
    const KdTreeStats& s = tree.stats();
    const std::uint32_t node_size = node_size_option.value_or(default_node_size(kind));
    const int bounces = max_bounces.value_or(kDefaultMaxBounces);
    const RayKindPlan plan = path ? plan_path_ray_kinds(scene, bounces, environment_light) : plan_ray_kinds(scene, max_depth);
    const Bounds bounds = scene.bounds();

    nlohmann::json j;
    j["scene"] = {{"name", source->name()},
                  {"hash", source->content_hash()},
                  {"triangles", scene.triangles.size()},
                  {"materials", scene.materials.size()},
                  {"lights", scene.lights.size()},
                  {"camera", scene.camera ? "scene" : "default framing"},
                  {"frames", animation.frames},
                  {"time", time}};
    if (!bounds.empty()) {
      j["scene"]["bounds"] = {{"lo", {bounds.lo.x, bounds.lo.y, bounds.lo.z}},
                              {"hi", {bounds.hi.x, bounds.hi.y, bounds.hi.z}}};
    }
    nlohmann::json split_levels = nlohmann::json::object();
    for (std::uint64_t size : {1024u, 2048u, 4096u, 8192u, 16384u}) {
      split_levels[std::to_string(size)] = base::split_level_for_capacity(
          s.nodes_per_level, base::LevelPlacement::contiguous_bytes(node_size), size);
    }
    // A BVH's leaves by size: how many hold 1, 2, ... triangles.
    std::map<std::uint32_t, std::uint64_t> leaf_sizes;
    if (const Bvh* bvh = tree.bvh()) {
      for (const auto& child : bvh->children()) {
        if (child.is_leaf()) ++leaf_sizes[child.count];
      }
    }
    nlohmann::json leaf_size_counts = nlohmann::json::object();
    for (const auto& [size, count] : leaf_sizes) leaf_size_counts[std::to_string(size)] = count;
    if (kind != AccelKind::KdTree) {
      nlohmann::json accel = {{"name", accel_name(kind)},
                              {"leaves_by_size", leaf_size_counts},
                              {"arity", accel_arity(kind)},
                              {"nodes", s.nodes},
                              {"leaves", s.leaves},
                              {"depth", s.depth},
                              {"nodes_per_level", s.nodes_per_level},
                              {"node_size", node_size},
                              {"bytes", s.nodes * node_size},
                              {"mean_leaf_size", s.mean_leaf_size},
                              {"primitive_references", s.primitive_references},
                              {"sah_cost", s.sah_cost},
                              {"build_seconds", s.build_seconds},
                              {"build_cpu_seconds", s.build_cpu_seconds},
                              {"loaded_from_tree_cache", s.loaded},
                              {"split_level_for_high_size", split_levels}};
      j["accel"] = accel;
    } else {
    j["kdtree"] = {{"nodes", s.nodes},
                   {"interior", s.interior},
                   {"leaves", s.leaves},
                   {"empty_leaves", s.empty_leaves},
                   {"depth", s.depth},
                   {"depth_limit", s.depth_limit},
                   {"nodes_per_level", s.nodes_per_level},
                   {"mean_leaf_size", s.mean_leaf_size},
                   {"mean_nonempty_leaf_size", s.mean_nonempty_leaf_size},
                   {"primitive_references", s.primitive_references},
                   {"sah_cost", s.sah_cost},
                   {"build_seconds", s.build_seconds},
                   {"build_cpu_seconds", s.build_cpu_seconds},
                   {"loaded_from_tree_cache", s.loaded},
                   {"node_size", node_size},
                   {"split_level_for_high_size", split_levels}};
    }
    nlohmann::json rays = nlohmann::json::object();
    for (const RayKind kind : plan.kinds) {
      const int k = static_cast<int>(kind);
      rays[std::string(ray_kind_name(kind))] =
          plan.cast[k] ? nlohmann::json("cast") : nlohmann::json("left out: " + plan.why_not[k]);
    }
    j["rays"] = rays;
    if (path) {
      j["rays_integrator"] = "path";
      j["rays_max_bounces"] = bounces;
      if (environment) j["rays_environment"] = *environment;
    } else {
      j["rays_max_depth"] = max_depth;
    }
    // The process's high-water mark so far: the scene loaded and its tree built.
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    const std::uint64_t peak_bytes = static_cast<std::uint64_t>(usage.ru_maxrss) * 1024;
    const double per_triangle = scene.triangles.empty() ? 0.0 : double(peak_bytes) / double(scene.triangles.size());
    j["peak_memory"] = {{"bytes", peak_bytes}, {"bytes_per_triangle", per_triangle}};

    if (format == "json") {
      std::fputs((j.dump(2) + "\n").c_str(), stdout);
      return 0;
    }
    if (format == "csv") {
      std::fputs(cli::field_value_csv(j).c_str(), stdout);
      return 0;
    }
    fmt::print("scene {}: {} triangles, {} materials, {} lights, {} frame(s), camera: {}\n",
               source->name(), scene.triangles.size(), scene.materials.size(), scene.lights.size(),
               animation.frames, scene.camera ? "from the scene" : "default framing");
    if (!bounds.empty()) {
      fmt::print("  bounds: ({:g}, {:g}, {:g}) - ({:g}, {:g}, {:g})\n", bounds.lo.x, bounds.lo.y,
                 bounds.lo.z, bounds.hi.x, bounds.hi.y, bounds.hi.z);
    }
    const char* built_or_loaded = s.loaded ? "loaded from the tree cache" : "built";
    if (kind == AccelKind::KdTree) {
      fmt::print("kd-tree: {} nodes ({} interior, {} leaves, {} empty), depth {} (limit {})\n", s.nodes,
                 s.interior, s.leaves, s.empty_leaves, s.depth, s.depth_limit);
      fmt::print("  mean leaf size {:.2f} ({:.2f} over non-empty leaves), SAH cost {:.2f}, {} in {:.3f} s ({:.3f} s CPU)\n",
                 s.mean_leaf_size, s.mean_nonempty_leaf_size, s.sah_cost, built_or_loaded, s.build_seconds,
                 s.build_cpu_seconds);
    } else {
      fmt::print("{}: {} nodes of {} bytes ({} bytes), {}-wide, {} leaves, depth {}\n", accel_name(kind), s.nodes,
                 node_size, s.nodes * node_size, accel_arity(kind), s.leaves, s.depth);
      std::string by_size;
      for (const auto& [size, count] : leaf_sizes) by_size += fmt::format("{}{}: {}", by_size.empty() ? "" : ", ", size, count);
      fmt::print("  mean leaf size {:.2f} (leaves by triangles {}), SAH cost {:.2f}, {} in {:.3f} s ({:.3f} s CPU)\n",
                 s.mean_leaf_size, by_size, s.sah_cost, built_or_loaded, s.build_seconds, s.build_cpu_seconds);
    }
    fmt::print("  nodes per level: {}\n", fmt::join(s.nodes_per_level, " "));
    fmt::print("  split level K for a high-level cache of 1K/2K/4K/8K/16K at {} bytes a node: {}/{}/{}/{}/{}\n",
               node_size, split_levels["1024"].get<int>(), split_levels["2048"].get<int>(),
               split_levels["4096"].get<int>(), split_levels["8192"].get<int>(),
               split_levels["16384"].get<int>());
    fmt::print("peak memory: {:.1f} MiB ({:.0f} bytes per triangle), the scene loaded and its {} built\n",
               double(peak_bytes) / (1 << 20), per_triangle, kind == AccelKind::KdTree ? "kd-tree" : accel_name(kind));
    if (path) {
      fmt::print("rays (path tracing, max bounces {}):\n", bounces);
    } else {
      fmt::print("rays (max depth {}):\n", max_depth);
    }
    for (const RayKind kind : plan.kinds) {
      const int k = static_cast<int>(kind);
      fmt::print("  {:<10} {}\n", ray_kind_name(kind), plan.cast[k] ? "cast" : "left out: " + plan.why_not[k]);
    }
    return 0;
  }, "the scene is");
}

}  // namespace

int info_command(int argc, char** argv) {
  return cli::run_command<InfoCommand>("tracer info",
                                      "Scene and acceleration-structure statistics: triangles, materials, lights,\n"
                                      "bounds, the SAH kd-tree's or a BVH's figures (--accel), and which ray kinds\n"
                                      "a render casts.", argc, argv);
}

}  // namespace nodetrace::tracer::tools
