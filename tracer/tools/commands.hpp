// The subcommands of `tracer`, each in its own file. Each registers its
// options on its CLI11 subcommand of the `tracer` app before the command line
// is parsed; after parsing, the chosen one's run() does the work and returns
// the exit code (0 success, 1 bad data, 2 bad usage).
#pragma once

#include <CLI/CLI.hpp>

#include <functional>
#include <memory>

namespace nodetrace::tracer::cli {

struct Subcommand {
  CLI::App* app;             // the subcommand, owned by the `tracer` app
  std::function<int()> run;  // the work, on the options parsed into it
};

// Adds subcommand `name` to `tracer` for a Command type that holds its
// options: `void add_options(CLI::App&)` binds them, `int run() const` uses them.
// The options live as long as the returned run function.
template <typename Command>
Subcommand make_subcommand(CLI::App& tracer, const char* name, const char* description) {
  CLI::App& app = *tracer.add_subcommand(name, description);
  auto command = std::make_shared<Command>();
  command->add_options(app);
  return {&app, [command] { return command->run(); }};
}

Subcommand add_render_command(CLI::App& tracer);  // tracer render [SCENE] -o TRACE
Subcommand add_info_command(CLI::App& tracer);    // tracer info SCENE
Subcommand add_scenes_command(CLI::App& tracer);  // tracer scenes: list built-in scenes

}  // namespace nodetrace::tracer::cli
