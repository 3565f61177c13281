// tracer scenes: list the built-in procedural scenes.
#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include <cstdio>
#include <exception>
#include <nlohmann/json.hpp>
#include <string>

#include "commands.hpp"
#include "nodetrace/cli/command_line.hpp"
#include "nodetrace/cli/csv_text.hpp"
#include "nodetrace/cli/format_option.hpp"
#include "nodetrace/cli/exit_status.hpp"
#include "nodetrace/tracer/scene/scene_loader.hpp"

namespace nodetrace::tracer::tools {

namespace {

// The options of `tracer scenes` and what it does with them.
struct ScenesCommand {
  std::string format = "table";

  void add_options(CLI::App& app);
  int run() const;
};

void ScenesCommand::add_options(CLI::App& app) {
  cli::add_format_option(app, format,
                         "csv: one table, a row per scene; json: {\"scenes\": [...], \"default\": NAME}");
}

int ScenesCommand::run() const {
  return cli::exit_status_of("tracer scenes", [&] {
    const auto scenes = builtin_scenes();
    const std::string default_name = default_scene_name();
    if (format == "json") {
      nlohmann::json list = nlohmann::json::array();
      for (const auto& scene : scenes) {
        list.push_back({{"name", scene.name},
                        {"description", scene.description},
                        {"default_size", scene.default_size},
                        {"triangles", scene.triangles},
                        {"min_size", scene.min_size},
                        {"max_size", scene.max_size},
                        {"min_triangles", scene.min_triangles},
                        {"max_triangles", scene.max_triangles},
                        {"default", scene.name == default_name}});
      }
      fmt::print("{}\n", nlohmann::json{{"scenes", list}, {"default", default_name}}.dump(2));
      return 0;
    }
    if (format == "csv") {
      std::string csv = cli::csv_line({"name", "triangles", "default_size", "min_size", "max_size", "min_triangles", "max_triangles",
                                       "default", "description"});
      for (const auto& scene : scenes) {
        csv += cli::csv_line({scene.name, std::to_string(scene.triangles), std::to_string(scene.default_size),
                              std::to_string(scene.min_size),
                              std::to_string(scene.max_size), std::to_string(scene.min_triangles),
                              std::to_string(scene.max_triangles), scene.name == default_name ? "true" : "false",
                              scene.description});
      }
      std::fputs(csv.c_str(), stdout);
      return 0;
    }
    fmt::print("{:<12} {:>10}  {:<7} {:<21} {}\n", "NAME", "TRIANGLES", "SIZES", "TRIANGLES BY SIZE", "DESCRIPTION");
    for (const auto& scene : scenes) {
      fmt::print("{:<12} {:>10}  {:<7} {:<21} {}{}\n", scene.name, scene.triangles,
                 fmt::format("{}..{}", scene.min_size, scene.max_size),
                 fmt::format("{}..{}", scene.min_triangles, scene.max_triangles), scene.description,
                 scene.name == default_name ? " (default)" : "");
    }
    fmt::print("\nTRIANGLES is the count at the default size; choose another with NAME:SIZE.\n");
    return 0;
  });
}

}  // namespace

int scenes_command(int argc, char** argv) {
  return cli::run_command<ScenesCommand>("tracer scenes",
      "List the built-in procedural scenes: name, triangle count at the default size, the accepted sizes "
      "and a description.\nUse one as SCENE (NAME or NAME:SIZE) in `tracer render` and `tracer info`.", argc, argv);
}

}  // namespace nodetrace::tracer::tools
