// cachesim: node-cache and Dinero-IV-compatible cache simulation.
// Dispatches to a subcommand; `dinero` takes Dinero IV's own option syntax,
// which CLI11 cannot parse, so dispatch happens before any parsing.
#include <cstdio>
#include <string_view>

#include "nodetrace/formats/standard_output.hpp"
#include "commands.hpp"

namespace {

constexpr const char* kUsage =
    "cachesim: simulate node caches and Dinero IV caches on traces\n"
    "\n"
    "Usage:\n"
    "  cachesim run TRACE... [options]      split / single node caches, one-pass sweeps\n"
    "  cachesim dinero [Dinero IV options]  a drop-in replacement for dineroIV\n"
    "  cachesim --version                   the version, as trace headers record it\n"
    "\n"
    "`cachesim SUBCOMMAND --help` describes each.\n";

}  // namespace

static int run(int argc, char** argv) {
  if (argc < 2) {
    std::fputs(kUsage, stderr);
    return 2;
  }
  const std::string_view subcommand = argv[1];
  if (subcommand == "-h" || subcommand == "--help") {
    std::fputs(kUsage, stdout);
    return 0;
  }
  if (subcommand == "--version") {  // the project's version, the one trace headers record
    std::printf("cachesim %s\n", NODETRACE_VERSION);
    return 0;
  }
  if (subcommand == "dinero") return nodetrace::cachesim::cli::dinero_command(argc - 1, argv + 1);
  if (subcommand == "run") return nodetrace::cachesim::cli::run_command(argc - 1, argv + 1);
  std::fprintf(stderr, "cachesim: unknown subcommand '%s'\n\n%s", argv[1], kUsage);
  return 2;
}

int main(int argc, char** argv) { return nodetrace::formats::finish_standard_output("cachesim", run(argc, argv)); }
