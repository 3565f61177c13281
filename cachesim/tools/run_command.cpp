#include <cstdio>

#include "commands.hpp"

namespace nodetrace::cachesim::cli {

int run_command(int, char**) {
  std::fputs("cachesim run: not implemented yet\n", stderr);
  return 2;
}

}  // namespace nodetrace::cachesim::cli
