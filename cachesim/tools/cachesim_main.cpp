// cachesim: node-cache and Dinero-IV-compatible cache simulation.
// Dispatches to a subcommand; `dinero` takes Dinero IV's own option syntax,
// which CLI11 cannot parse, so dispatch happens before any parsing.
#include <cstdio>
#include <string_view>

#include "nodetrace/base/standard_output.hpp"
#include "commands.hpp"
#include "nodetrace/cli/subcommand_dispatch.hpp"

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
  using namespace nodetrace::cachesim::tools;
  return nodetrace::cli::dispatch_subcommand("cachesim", kUsage, argc, argv,
                             {{"dinero", dinero_command}, {"run", run_command}});
}

int main(int argc, char** argv) { return nodetrace::base::finish_standard_output("cachesim", run(argc, argv)); }
