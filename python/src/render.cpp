// nodetrace.render(): a render with the tracer's options, parsed by the
// tracer's own option layer (nodetrace/tracer/options), its image returned;
// with simulate=, also the report of `tracer render --simulate` (the same
// in-render simulation, nodetrace/tracer/simulate).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <CLI/CLI.hpp>

#include <algorithm>
#include <filesystem>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "interruptible.hpp"
#include "option_arguments.hpp"
#include "captured_stderr.hpp"
#include "render.hpp"
#include "simulate.hpp"
#include "nodetrace/tracer/options/render_options.hpp"
#include "nodetrace/tracer/options/trace_output_options.hpp"
#include "nodetrace/tracer/render/trace_job.hpp"
#include "nodetrace/tracer/scene/scene_loader.hpp"
#include "nodetrace/tracer/simulate/in_render_simulation.hpp"

namespace py = pybind11;

namespace nodetrace::python {

namespace {

// The options of `tracer render` that a render() takes, bound as the
// program binds them.
struct RenderCall {
  tracer::tools::TraceOutputOptions trace_output;
  tracer::tools::SceneCommandOptions scene;
  tracer::tools::RenderCommandOptions render;
  CLI::Option* max_depth_option = nullptr;

  // Parses the words; throws CLI::ParseError (ValueError) as the program
  // would exit 2 with its message.
  void parse(std::vector<std::string> words) {
    CLI::App app{"nodetrace.render", "nodetrace.render"};
    tracer::tools::add_trace_output_option(app, trace_output);
    tracer::tools::add_trace_record_options(app, trace_output);
    tracer::tools::add_scene_options(app, scene);
    tracer::tools::add_render_options(app, render);
    max_depth_option = app.get_option("--max-depth");
    std::reverse(words.begin(), words.end());  // CLI11 takes them last first
    app.parse(words);
  }

  tracer::TraceJobOptions job() const {
    tracer::tools::check_depth_options(render.integrator, max_depth_option->count() != 0,
                                       render.max_bounces.has_value());
    const bool traces_optional = true;  // the image is what a render() without output= is for
    tracer::TraceJobOptions options =
        tracer::tools::make_job_options(render, scene, trace_output.output, traces_optional);
    tracer::tools::apply_trace_output(trace_output, options);
    options.keep_image = true;
    return options;
  }
};

py::array_t<float> image_array(const tracer::Image& image) {
  py::array_t<float> array({image.height, image.width, 3});
  float* out = array.mutable_data();
  for (const tracer::Vec3& p : image.pixels) {
    *out++ = p.x;
    *out++ = p.y;
    *out++ = p.z;
  }
  return array;
}

// simulate=: parsed as `tracer render --simulate` parses its options, its
// error raised with the message that program prints.
cachesim::SimulationOptions simulate_options(const py::object& simulate) {
  const std::vector<std::string> words = simulation_words(simulate, "simulate");
  return parse_simulation_options("tracer render --simulate", [&](cachesim::SimulationOptions& options) {
    return tracer::simulate::InRenderSimulation::parse_words(words, options);
  });
}

}  // namespace

void bind_render(py::module_& module) {
  module.def(
      "render",
      [](std::optional<std::filesystem::path> scene, std::optional<std::filesystem::path> output,
         const py::object& simulate, const py::kwargs& options) -> py::object {
        std::vector<std::string> words = option_words(options);
        if (output) {
          words.push_back("--output");
          words.push_back(output->string());
        }
        RenderCall call;
        call.parse(words);
        tracer::TraceJobOptions job = call.job();
        if (job.output == "-") throw base::UsageError("output='-': name a file (standard output is Python's)");
        // Every layout simulated as the records are made, as `tracer render --simulate` does.
        std::optional<tracer::simulate::InRenderSimulation> simulation;
        if (!simulate.is_none()) {
          cachesim::SimulationOptions parsed = simulate_options(simulate);
          simulation.emplace();
          simulation->plan(std::move(parsed));
          std::vector<std::string> layout_names;
          for (const auto& choice : tracer::tools::layout_choices(call.render)) layout_names.push_back(choice.name);
          job.sink_makers.push_back(
              simulation->sink_maker(tracer::simulate::InRenderSimulation::trace_names(job, layout_names)));
        }
        const std::string spec = scene ? scene->string() : tracer::default_scene_name();
        const auto source =
            tracer::open_scene(spec, tracer::tools::scene_load_options(call.scene, job.build.threads));
        const auto warnings = py::module_::import("warnings");
        for (const auto& warning : source->warnings()) warnings.attr("warn")("nodetrace.render: " + warning);
        const std::unique_ptr<tracer::TreeCache> tree_cache =
            tracer::tools::open_tree_cache(call.scene.tree_cache, "nodetrace.render");
        job.tree_cache = tree_cache.get();
        const tracer::TraceJobResult result = run_interruptibly([&](const SignalCheck& stop) {
          // The renderer reports progress after each block of pixels: a stop is answered there.
          return tracer::run_trace_job(*source, job, [&](double) { stop(); });
        });
        for (const auto& note : result.notes) warnings.attr("warn")("nodetrace.render: note: " + note);
        if (!simulation) return image_array(*result.image);
        return py::make_tuple(image_array(*result.image), report_rows(simulation->report()));
      },
      py::arg("scene") = py::none(), py::kw_only(), py::arg("output") = py::none(), py::arg("simulate") = py::none(),
      "Renders SCENE (an .obj or .aff file, or a built-in scene's name; default: the default built-in scene) "
      "with the options of `tracer render`, given as keywords (max_depth=10 for --max-depth 10, a list for "
      "options of several values, True for a flag), and returns the first frame's image as a float32 array of "
      "height x width x 3 (RGB, top row first; path tracing: the mean radiance). output= writes the trace as "
      "`tracer render -o` does. simulate= (cachesim run's options as simulate() takes them: a text, a list of "
      "words or a dict) simulates caches on every layout's records as they are made, as `tracer render --simulate "
      "OPTIONS --report FILE` does, and returns (image, rows): rows the report's rows (SimulationRows, a trace "
      "column per layout). A wrong option name or value raises ValueError with the program's message.");
}

}  // namespace nodetrace::python
