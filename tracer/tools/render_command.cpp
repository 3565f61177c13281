// tracer render [SCENE] -o TRACE: render with the Whitted ray tracer (or the
// path tracer) and
// write every kd-tree node fetch as a level-tagged trace.
#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <fmt/core.h>

#include <bit>
#include <chrono>
#include <filesystem>
#include <utility>
#include <cstdio>
#include <new>
#include <optional>
#include <string>

#include "commands.hpp"
#include "nodetrace/cli/command_line.hpp"
#include "nodetrace/cli/distinct_outputs.hpp"
#include "nodetrace/cli/exit_status.hpp"
#include "nodetrace/cli/progress_line.hpp"
#include "nodetrace/cli/archive_option.hpp"
#include "nodetrace/cli/zstd_level_option.hpp"
#include "nodetrace/base/error.hpp"
#include "nodetrace/base/output_file.hpp"
#include "nodetrace/base/standard_output.hpp"
#include "nodetrace/formats/write/trace_output.hpp"
#include "nodetrace/tracer/scene/scene_loader.hpp"
#include "nodetrace/tracer/simulate/in_render_simulation.hpp"
#include "nodetrace/tracer/render/trace_job.hpp"
#include "trace_info_output.hpp"
#include "nodetrace/base/output_file.hpp"
#include "nodetrace/tracer/options/render_options.hpp"
#include "nodetrace/tracer/options/trace_output_options.hpp"

namespace nodetrace::tracer::tools {

namespace {

// Rays per core-second: each kind's from the traversal time of the rays the
// render timed (one in RayKindTimer::kTimeEvery, records made included), and
// all rays' from the render workers' CPU time (shading and handing records
// on included). Timings vary from run to run: the summary only.
void print_rays_per_core(const RenderStats& t, const RayKindPlan& plan) {
  std::string kinds;
  for (const RayKind kind : plan.kinds) {
    const double rate = t.traversal_rays_per_second(kind);
    if (rate <= 0) continue;
    kinds += fmt::format("{}{} {:.2f} M", kinds.empty() ? "" : ", ", ray_kind_name(kind), rate / 1e6);
  }
  if (!kinds.empty()) std::fprintf(stderr, "  rays/s per core, traversal: %s\n", kinds.c_str());
  if (t.cpu_seconds > 0) {
    std::fprintf(stderr, "  rays/s per core, whole render: %.2f M (render workers' CPU %.3f s)\n",
                 double(t.total_rays()) / t.cpu_seconds / 1e6, t.cpu_seconds);
  }
}

// "built in 0.72 s", or what the tree cache gave: the time is then the
// loading's.
std::string tree_origin(const TraceJobResult& result) {
  double seconds = 0;
  std::size_t loaded = 0;
  for (const auto& f : result.frames) {
    seconds += f.tree.build_seconds;
    loaded += f.tree.loaded;
  }
  if (loaded == 0) return fmt::format("built in {:.2f} s", seconds);
  if (loaded == result.frames.size()) return fmt::format("loaded from the tree cache in {:.2f} s", seconds);
  return fmt::format("built or loaded in {:.2f} s ({} of {} frames' trees from the tree cache)", seconds, loaded,
                     result.frames.size());
}

void print_summary(const TraceJobResult& result, const TraceJobOptions& options,
                   const std::string& scene_name) {
  const RenderStats& t = result.total;
  const auto& first = result.frames.front();
  const auto describe = [](LayoutKind kind, std::uint32_t split_level) {
    return kind == LayoutKind::Hybrid ? fmt::format("hybrid (split level {})", split_level)
                                      : std::string(layout_name(kind));
  };
  std::string layout = describe(options.layout, first.split_level);
  for (std::size_t i = 0; i < options.other_layouts.size(); ++i) {
    layout += ", " + describe(options.other_layouts[i].layout, first.other_split_levels[i]);
  }
  const RenderOptions& r = options.render;
  const std::string integrator =
      r.integrator == Integrator::Path
          ? fmt::format("path tracing, {} spp, max bounces {}{}", r.path.samples_per_pixel, r.path.max_bounces,
                        r.environment ? fmt::format(", environment {} {}x{}", r.environment->name(),
                                                    r.environment->width(), r.environment->height())
                                      : std::string())
          : fmt::format("max depth {}", r.max_depth);
  std::fprintf(stderr, "tracer: %s, %dx%d, %s, %zu frame(s), layout%s %s\n", scene_name.c_str(), r.width, r.height,
               integrator.c_str(), result.frames.size(), options.other_layouts.empty() ? "" : "s", layout.c_str());
  const std::string accel = options.accel == AccelKind::KdTree ? "kd-tree" : std::string(accel_name(options.accel));
  std::fprintf(stderr,
               "  %s: %llu triangles, %llu nodes, %llu leaves (%llu empty), depth %u, %s\n",
               accel.c_str(), static_cast<unsigned long long>(first.triangles),
               static_cast<unsigned long long>(first.tree.nodes),
               static_cast<unsigned long long>(first.tree.leaves),
               static_cast<unsigned long long>(first.tree.empty_leaves), first.tree.depth,
               tree_origin(result).c_str());
  std::string kinds;
  for (const RayKind kind : result.plan.kinds) {
    const int k = static_cast<int>(kind);
    if (!kinds.empty()) kinds += ", ";
    kinds += fmt::format("{} {}", ray_kind_name(kind), t.rays[k]);
    if (!result.plan.cast[k]) kinds += " (" + result.plan.why_not[k] + ")";
  }
  std::fprintf(stderr, "  rays: %s; total %llu\n", kinds.c_str(),
               static_cast<unsigned long long>(t.total_rays()));
  const double rays = std::max<double>(1.0, double(t.total_rays()));
  std::fprintf(stderr,
               "  node fetches: %llu (%.2f per ray), leaves visited: %llu, triangles tested: %llu\n",
               static_cast<unsigned long long>(t.node_fetches), double(t.node_fetches) / rays,
               static_cast<unsigned long long>(t.leaf_visits),
               static_cast<unsigned long long>(t.triangle_tests));
  if (const auto& sampling = options.sampling) {
    std::uint64_t bands = 0;
    for (const auto& f : result.frames) bands += f.bands_rendered;
    std::fprintf(stderr, "  sampled: one band of %u row(s) in every %llu (seed %llu): %llu of %llu bands rendered\n",
                 sampling->band_height, static_cast<unsigned long long>(sampling->every),
                 static_cast<unsigned long long>(sampling->seed), static_cast<unsigned long long>(bands),
                 static_cast<unsigned long long>(band_count(options.render.height, sampling->band_height) *
                                                 result.frames.size()));
  }
  if (t.nonfinite_samples) {
    std::fprintf(stderr, "  samples dropped (NaN or infinite throughput or radiance): %llu\n",
                 static_cast<unsigned long long>(t.nonfinite_samples));
  }
  std::fprintf(stderr, "  render: %.3f s, %.3f M rays/s; %llu records\n", t.seconds,
               t.seconds > 0 ? double(t.total_rays()) / t.seconds / 1e6 : 0.0,
               static_cast<unsigned long long>(t.records));
  print_rays_per_core(t, result.plan);
}

// The options of `tracer render` and what it does with them.
struct RenderCommand {
  std::string scene_spec, image;
  std::vector<std::string> simulations, reports;
  std::string trace_info;
  CLI::Option* image_option = nullptr;
  CLI::Option* report_option = nullptr;
  CLI::Option* trace_info_option = nullptr;
  std::string pfm, variance_pfm;
  CLI::Option* pfm_option = nullptr;
  CLI::Option* max_depth_option = nullptr;
  CLI::Option* variance_pfm_option = nullptr;
  bool quiet = false;
  bool discard = false;
  TraceOutputOptions trace_output;  // -o, --records, --streams, compression
  SceneCommandOptions scene_options;
  RenderCommandOptions render_options;

  void add_options(CLI::App& app);
  int run() const;

 private:
  void check_outputs(const TraceJobOptions& options, const std::vector<cli::NamedOutput>& tables) const;
  void check_simulations() const;
  void write_report(const std::string& path, const cachesim::SimulationReport& text) const;
};

// Each --simulate has its --report; standard output holds one stream.
void RenderCommand::check_simulations() const {
  if (simulations.size() != reports.size()) {
    throw base::UsageError(fmt::format("--simulate and --report go in pairs (each simulation's report goes to the "
                                       "--report in the same place): {} --simulate, {} --report",
                                       simulations.size(), reports.size()));
  }
  std::vector<std::string> seen;
  for (const auto& report : reports) {
    if (report == "-" && trace_output.output == "-") {
      throw base::UsageError("--report - and -o -: standard output holds one of them; name a file for the other");
    }
    if (std::find(seen.begin(), seen.end(), report) != seen.end()) {
      throw base::UsageError(fmt::format("--report {}: named twice; each simulation needs a file of its own", report));
    }
    seen.push_back(report);
  }
}

// The report as cachesim run prints it: its standard output in --report
// (written whole or not at all), its notes on standard error.
void RenderCommand::write_report(const std::string& path, const cachesim::SimulationReport& text) const {
  if (path == "-") {
    std::fwrite(text.out.data(), 1, text.out.size(), stdout);
    std::fflush(stdout);
  } else {
    base::OutputFile file(path);
    file.write(text.out);
    file.commit();
  }
  std::fwrite(text.err.data(), 1, text.err.size(), stderr);
}

// An empty name is no output, two outputs into one file spoil each other, and
// an output whose folder is missing or not writable would fail only after
// the whole render: all are refused before it starts.
// `tables`: the files of the --simulate options' own tables (--per-level ...).
void RenderCommand::check_outputs(const TraceJobOptions& options,
                                  const std::vector<cli::NamedOutput>& tables) const {
  std::vector<std::pair<CLI::Option*, std::string>> outputs{
      {image_option, image}, {pfm_option, pfm}, {variance_pfm_option, variance_pfm}};
  if (trace_info_option->count() != 0) {
    // Each layout's file: a pattern is checked as the names it makes.
    const std::vector<std::string> files =
        trace_info.empty() ? std::vector<std::string>{trace_info}
                           : layout_files(layout_choices(render_options), trace_info, "--trace-info");
    for (const auto& file : files) outputs.emplace_back(trace_info_option, file);
  }
  for (const auto& report : reports) outputs.emplace_back(report_option, report);
  if (trace_output.output_option->count() != 0) {
    outputs.emplace_back(trace_output.output_option, options.output);
    for (const auto& other : options.other_layouts) outputs.emplace_back(trace_output.output_option, other.output);
  }
  std::vector<cli::NamedOutput> named;
  for (const auto& [option, path] : outputs) {
    if (option->count() == 0) continue;
    if (path.empty()) {
      throw base::UsageError(fmt::format("{}: an empty name: give a file name{}", option->get_name(),
                                         option == trace_output.output_option ? ", or - for standard output" : ""));
    }
    named.push_back({option->get_name(), path});
  }
  // The image and a trace in one file (or both on standard output) would
  // interleave or overwrite each other; a device (/dev/null) takes both.
  // (The tables' files are checked by cachesim's own code, as to be written.)
  std::vector<cli::NamedOutput> all = named;
  all.insert(all.end(), tables.begin(), tables.end());
  cli::check_distinct_outputs(all);
  for (const auto& [option, path] : named) {
    if (path == "-") continue;
    const std::filesystem::path folder = std::filesystem::path(path).parent_path();
    if (!folder.empty() && !std::filesystem::is_directory(folder)) {
      throw base::IoError(fmt::format("{}: cannot write: folder '{}' does not exist (checked before rendering)",
                                      path, folder.string()));
    }
    try {
      base::check_output_writable(path);
    } catch (const base::IoError& error) {
      throw base::IoError(std::string(error.what()) + " (checked before rendering)");
    }
  }
}

// Several layouts differ only in their records: a run that keeps none of
// them (no -o, --simulate, --trace-info or --discard-records) asked for
// something else.
void refuse_layouts_for_nothing(const std::vector<LayoutChoice>& choices) {
  if (choices.size() < 2) return;
  std::string names;
  for (const auto& choice : choices) names += (names.empty() ? "" : ", ") + choice.name;
  throw base::UsageError(fmt::format("{} layouts ({}) and nothing takes their records: give -o with {{layout}} in "
                                     "the file name (one trace each), --simulate or --trace-info",
                                     choices.size(), names));
}

// Din has no size field: Dinero IV and cachesim read every din record as 4
// bytes, so a larger node that straddles a block boundary counts one fetch,
// not the two its bytes need.
void warn_of_din_node_size(const TraceJobOptions& options) {
  const std::uint32_t node_size = options.render.addresses.node_size;
  if (options.output.empty() || options.form != formats::RecordForm::Din || node_size <= 4) return;
  // Aligned power-of-two nodes of at most 8 bytes stay whole in blocks of 8
  // bytes and more (cachesim's default block): nothing is lost there.
  const bool whole_in_blocks = std::has_single_bit(node_size) && node_size <= 8 &&
                               options.render.addresses.node_base % node_size == 0;
  if (whole_in_blocks) return;
  std::fprintf(stderr,
               "tracer render: warning: din records carry no size, so Dinero IV and cachesim read each %u-byte node "
               "as 4 bytes: where a cache block splits a node, its second block is not fetched; xdin records "
               "(--records xdin, or a .xdin.zst name) keep the size\n",
               node_size);
}

void RenderCommand::add_options(CLI::App& app) {
  app.add_option("scene", scene_spec,
                 "an .obj or .aff file, or a built-in scene's name (NAME or NAME:SIZE); "
                 "default: the default built-in scene");
  add_trace_output_option(app, trace_output);
  image_option = app.add_option("--image", image,
                                 "also write the first frame as a PNG (path tracing: the mean radiance, clamped to "
                                 "0..1, through the sRGB curve)");
  pfm_option = app.add_option("--pfm", pfm, "also write the first frame as a float PFM (path tracing: the mean radiance)");
  variance_pfm_option = app.add_option("--variance-pfm", variance_pfm,
                                       "--integrator path: also write each pixel's sample variance as a float PFM");
  add_trace_record_options(app, trace_output);
  app.add_flag("--discard-records", discard,
               "make every record but write none: the cost of recording alone (benchmarks)")
      ->excludes("--output");
  app.add_option("--simulate", simulations,
                 "also simulate node caches on the records as they are made, in this process: \"OPTIONS\" are "
                 "cachesim run's (no trace names), over every layout, or over one with \"LAYOUT=OPTIONS\" (a "
                 "{layout} name); the report, cachesim run's over the container traces, goes to the --report in "
                 "the same place; may be repeated")
      ->type_name("\"[LAYOUT=]OPTIONS\"")
      ->expected(1)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  report_option = app.add_option("--report", reports,
                                  "file for the report of the --simulate in the same place (- for standard output)")
                      ->type_name("FILE")
                      ->expected(1)
                      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  trace_info_option = app.add_option("--trace-info", trace_info,
                                     "write each layout's trace header and the render's totals as JSON to FILE "
                                     "({layout} for several layouts), for a trace not kept")
                          ->type_name("FILE");
  app.add_flag("-q,--quiet", quiet, "no summary on standard error");
  add_scene_options(app, scene_options);
  add_render_options(app, render_options);
  max_depth_option = app.get_option("--max-depth");
}

int RenderCommand::run() const {
  return cli::exit_status_of("tracer render", [&] {
    check_simulations();
    check_depth_options(render_options.integrator, max_depth_option->count() != 0,
                        render_options.max_bounces.has_value());
    // Several layouts need -o's {layout} only when -o is given: without it
    // no trace is written, and the records go to --simulate, --trace-info or
    // --discard-records.
    const bool traces_optional = !simulations.empty() || trace_output.output_option->count() == 0;
    if (trace_output.output_option->count() == 0 && simulations.empty() && trace_info_option->count() == 0 && !discard) {
      refuse_layouts_for_nothing(layout_choices(render_options));
    }
    TraceJobOptions options = make_job_options(render_options, scene_options, trace_output.output, traces_optional);
    std::vector<std::unique_ptr<simulate::InRenderSimulation>> simulated;
    const std::vector<LayoutChoice> choices = layout_choices(render_options);
    std::vector<std::string> layout_names;
    for (const auto& choice : choices) layout_names.push_back(choice.name);
    for (const auto& text : simulations) {
      simulated.push_back(std::make_unique<simulate::InRenderSimulation>());
      if (const std::optional<int> status = simulated.back()->parse(text, layout_names)) return *status;
      options.sink_makers.push_back(simulated.back()->sink_maker(simulate::InRenderSimulation::trace_names(options, layout_names)));
    }
    std::vector<cli::NamedOutput> tables;
    for (const auto& simulation : simulated) {
      const std::vector<cli::NamedOutput> files = simulation->table_files();
      tables.insert(tables.end(), files.begin(), files.end());
    }
    check_outputs(options, tables);
    // Read before the scene and any output: a bad map leaves nothing behind.
    if (render_options.environment) options.render.environment = load_environment_map(*render_options.environment);
    options.image = image;
    options.pfm = pfm;
    options.variance_pfm = variance_pfm;
    options.discard_records = discard;
    apply_trace_output(trace_output, options);
    base::refuse_binary_on_terminal(trace_output.output, "a trace");
    warn_of_din_node_size(options);
    if (!trace_info.empty()) {
      options.sink_makers.push_back(trace_info_maker(layout_files(choices, trace_info, "--trace-info")));
    }
    const std::string spec = scene_spec.empty() ? default_scene_name() : scene_spec;
    const auto source = open_scene(spec, scene_load_options(scene_options, options.build.threads));
    for (const auto& warning : source->warnings()) std::fprintf(stderr, "tracer render: warning: %s\n", warning.c_str());

    cli::ProgressLine progress_line(!quiet);
    Renderer::Progress progress;
    if (progress_line.shown()) {
      // The renderer reports the fraction done of every frame's pixels.
      const std::uint64_t pixels = static_cast<std::uint64_t>(options.render.width) *
                                   static_cast<std::uint64_t>(options.render.height) * options.frames.count();
      progress = [&, pixels](double fraction) {
        progress_line.update_count("rendering " + source->name(), static_cast<std::uint64_t>(fraction * double(pixels)),
                                   pixels, "pixels");
      };
    }
    const std::unique_ptr<TreeCache> tree_cache = open_tree_cache(scene_options.tree_cache, "tracer render");
    options.tree_cache = tree_cache.get();
    const TraceJobResult result = run_trace_job(*source, options, progress);
    progress_line.clear();
    for (const auto& note : result.notes) std::fprintf(stderr, "tracer render: note: %s\n", note.c_str());
    for (std::size_t i = 0; i < simulated.size(); ++i) write_report(reports[i], simulated[i]->report());
    if (!quiet) print_summary(result, options, source->name());
    return 0;
  }, "the scene or image is");
}

}  // namespace

int render_command(int argc, char** argv) {
  return cli::run_command<RenderCommand>("tracer render",
                                        "Render a scene with a Whitted ray tracer (or a path tracer: --integrator path)\n"
                                        "over a SAH kd-tree or a BVH (--accel)\n"
                                        "and write every node fetch (address, node level) as a trace.", argc, argv);
}

}  // namespace nodetrace::tracer::tools
