// tracer: render scenes with a Whitted ray tracer over a kd-tree and write
// level-tagged node-fetch traces. The subcommands are CLI11 subcommands (as
// in tracetool); tracer's own usage text and messages are kept.
#include <CLI/CLI.hpp>

#include <cstdio>
#include <string>
#include <vector>

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
    "  tracer --version                          the version, as trace headers record it\n"
    "\n"
    "SCENE is an .obj or .aff file or a built-in scene's name.\n"
    "`tracer SUBCOMMAND --help` describes each.\n";

}  // namespace

static int run(int argc, char** argv) {
  namespace cli = nodetrace::tracer::cli;
  CLI::App app{"render scenes and record every kd-tree node fetch as a trace", "tracer"};
  // NODETRACE_VERSION is the project's version, the one trace headers record as "producer".
  app.set_version_flag("--version", std::string("tracer ") + NODETRACE_VERSION);
  // At most one: after it, a word that names another subcommand is an argument
  // (`tracer render info` renders a scene file called info).
  app.require_subcommand(0, 1);
  const std::vector<cli::Subcommand> subcommands = {cli::add_render_command(app), cli::add_info_command(app),
                                                    cli::add_scenes_command(app)};
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& help) {
    if (app.get_help_ptr()->count() > 0) {  // tracer --help: the usage above
      std::fputs(kUsage, stdout);
      return 0;
    }
    return app.exit(help);  // a subcommand's help, from CLI11
  } catch (const CLI::CallForVersion& version) {
    return app.exit(version);
  } catch (const CLI::ParseError& error) {
    if (app.get_subcommands().empty()) {
      std::fprintf(stderr, "tracer: unknown subcommand '%s'\n\n%s", argv[1], kUsage);
      return 2;
    }
    app.exit(error);
    return 2;  // CLI11 has its own codes; ours: 2
  }
  for (const cli::Subcommand& subcommand : subcommands) {
    if (subcommand.app->parsed()) return subcommand.run();
  }
  std::fputs(kUsage, stderr);  // no subcommand
  return 2;
}

int main(int argc, char** argv) { return nodetrace::formats::finish_standard_output("tracer", run(argc, argv)); }
