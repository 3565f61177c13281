// The subcommands of `tracer`, each in its own file. Each takes the
// arguments from its name on and returns the exit code (0 success, 1 bad
// data, 2 bad usage).
#pragma once

namespace nodetrace::tracer::tools {

int render_command(int argc, char** argv);  // tracer render [SCENE] -o TRACE
int info_command(int argc, char** argv);    // tracer info SCENE
int scenes_command(int argc, char** argv);  // tracer scenes: list built-in scenes

}  // namespace nodetrace::tracer::tools
