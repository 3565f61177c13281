// Parsing one command's options with CLI11, the same way in every program:
// --help and --version print and exit 0, a parse error prints "NAME: " and
// CLI11's message and exits 2 (CLI11's own codes are not ours).
#pragma once

#include <CLI/CLI.hpp>

#include <optional>

namespace nodetrace::cli {

// Parses argv into `app`; the exit status when parsing ends the run, else nullopt.
std::optional<int> parse_command_line(CLI::App& app, int argc, char** argv);

// A subcommand whose options a Command type holds: `void add_options(CLI::App&)`
// binds them, `int run() const` does the work and returns the exit status.
// argv[0] is the subcommand's name; `name` is how usage shows it ("tracer render").
template <typename Command>
int run_command(const char* name, const char* description, int argc, char** argv) {
  CLI::App app{description, name};
  Command command;
  command.add_options(app);
  if (const std::optional<int> status = parse_command_line(app, argc, argv)) return *status;
  return command.run();
}

}  // namespace nodetrace::cli
