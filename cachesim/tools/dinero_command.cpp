#include <cstdio>

#include "commands.hpp"

namespace nodetrace::cachesim::cli {

int dinero_command(int, char**) {
  std::fputs("cachesim dinero: not implemented yet\n", stderr);
  return 2;
}

}  // namespace nodetrace::cachesim::cli
