// The dispatch both cachesim programs share: `PROGRAM SUBCOMMAND ARGS...`,
// `--help` and `--version` before any option parsing (`cachesim dinero`
// takes Dinero IV's own option syntax, which CLI11 cannot parse).
#pragma once

#include <cstdio>
#include <initializer_list>
#include <string>
#include <string_view>

#include "nodetrace/base/standard_output.hpp"

namespace nodetrace::cli {

struct Subcommand {
  std::string_view name;
  int (*command)(int argc, char** argv);  // the arguments from the subcommand's name on
};

// Runs the subcommand argv[1] names; exit 2 with the usage when there is none
// or it is unknown.
inline int dispatch_subcommand(const char* program, const char* usage, int argc, char** argv,
                               std::initializer_list<Subcommand> subcommands) {
  if (argc < 2) {
    std::fputs(usage, stderr);
    return 2;
  }
  const std::string_view name = argv[1];
  if (name == "-h" || name == "--help") {
    std::fputs(usage, stdout);
    return 0;
  }
  if (name == "--version") {  // the project's version, the one trace headers record
    std::printf("%s %s\n", program, NODETRACE_VERSION);
    return 0;
  }
  for (const Subcommand& subcommand : subcommands) {
    if (name != subcommand.name) continue;
    const int status = subcommand.command(argc - 1, argv + 1);
    // A report lost to a closed pipe is the subcommand's error, named as
    // its others are ("cachesim run: <stdout>: cannot write: Broken pipe");
    // main's own check then finds the status failed and says nothing more.
    return base::finish_standard_output((std::string(program) + " " + argv[1]).c_str(), status);
  }
  std::fprintf(stderr, "%s: unknown subcommand '%s'\n\n%s", program, argv[1], usage);
  return 2;
}

}  // namespace nodetrace::cli
