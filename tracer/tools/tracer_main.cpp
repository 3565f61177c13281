// tracer: render scenes with a Whitted ray tracer over a kd-tree and write
// level-tagged node-fetch traces.

#include "nodetrace/base/standard_output.hpp"
#include "commands.hpp"
#include "nodetrace/cli/subcommand_dispatch.hpp"

namespace {

constexpr const char* kUsage =
    "tracer: render scenes and record every kd-tree node fetch as a trace\n"
    "\n"
    "Usage:\n"
    "  tracer render [SCENE] -o TRACE [options]  render and write a node trace\n"
    "  tracer info SCENE                         scene and kd-tree statistics\n"
    "  tracer scenes                             list the built-in scenes\n"
    "  tracer --version                          the version, as trace headers record it\n"
    "\n"
    "SCENE is an .obj or .aff file or a built-in scene's name.\n"
    "`tracer SUBCOMMAND --help` describes each.\n";

}  // namespace

static int run(int argc, char** argv) {
  using namespace nodetrace::tracer::tools;
  return nodetrace::cli::dispatch_subcommand(
      "tracer", kUsage, argc, argv,
      {{"render", render_command}, {"info", info_command}, {"scenes", scenes_command}});
}

int main(int argc, char** argv) { return nodetrace::base::finish_standard_output("tracer", run(argc, argv)); }
