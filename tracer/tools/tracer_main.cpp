// tracer: render scenes with a Whitted ray tracer over a kd-tree and write
// level-tagged node-fetch traces.
#include <cstdio>
#include <string_view>

#include "nodetrace/formats/standard_output.hpp"
#include "commands.hpp"

namespace {

constexpr const char* kUsage =
    "tracer: render scenes and record every kd-tree node fetch as a trace\n"
    "\n"
    "Usage:\n"
    "  tracer render [SCENE] -o TRACE [options]  render and write a node trace\n"
    "  tracer info SCENE                         scene and kd-tree statistics\n"
    "  tracer scenes                             list the built-in scenes\n"
    "\n"
    "SCENE is an .obj or .aff file or a built-in scene's name.\n"
    "`tracer SUBCOMMAND --help` describes each.\n";

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
  namespace cli = nodetrace::tracer::cli;
  if (subcommand == "render") return cli::render_command(argc - 1, argv + 1);
  if (subcommand == "info") return cli::info_command(argc - 1, argv + 1);
  if (subcommand == "scenes") return cli::scenes_command(argc - 1, argv + 1);
  std::fprintf(stderr, "tracer: unknown subcommand '%s'\n\n%s", argv[1], kUsage);
  return 2;
}

int main(int argc, char** argv) { return nodetrace::formats::finish_standard_output("tracer", run(argc, argv)); }
