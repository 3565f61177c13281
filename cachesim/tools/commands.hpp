// The subcommands of `cachesim`, each in its own file. Each takes the
// arguments after its name and returns the process exit code
// (0 success, 1 bad data, 2 bad usage).
#pragma once

namespace nodetrace::cachesim::tools {

// What runs out of memory in these programs, for cli::exit_status_of.
inline constexpr const char* kTooLarge = "the caches or trace frames are";

int dinero_command(int argc, char** argv);  // cachesim dinero [Dinero IV options]
int run_command(int argc, char** argv);     // cachesim run TRACE... [options]

}  // namespace nodetrace::cachesim::tools
