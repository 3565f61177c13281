#include <cstdio>

#include "commands.hpp"

namespace nodetrace::tracer::cli {

int info_command(int, char**) {
  std::fputs("tracer info: not implemented yet\n", stderr);
  return 2;
}

}  // namespace nodetrace::tracer::cli
