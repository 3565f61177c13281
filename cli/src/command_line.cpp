#include "nodetrace/cli/command_line.hpp"

#include <cstdio>

namespace nodetrace::cli {

std::optional<int> parse_command_line(CLI::App& app, int argc, char** argv) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    if (error.get_exit_code() == 0) return app.exit(error) == 0 ? 0 : 2;  // --help, --version
    // Like every other error: the program and subcommand first.
    std::fflush(stdout);
    std::fprintf(stderr, "%s: %s\nRun with --help for the accepted options and values.\n",
                 app.get_name().c_str(), error.what());
    return 2;
  }
  return std::nullopt;
}

}  // namespace nodetrace::cli
