#include <cstdio>

#include "commands.hpp"

namespace nodetrace::tracer::cli {

int scenes_command(int, char**) {
  std::fputs("tracer scenes: not implemented yet\n", stderr);
  return 2;
}

}  // namespace nodetrace::tracer::cli
