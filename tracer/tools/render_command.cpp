#include <cstdio>

#include "commands.hpp"

namespace nodetrace::tracer::cli {

int render_command(int, char**) {
  std::fputs("tracer render: not implemented yet\n", stderr);
  return 2;
}

}  // namespace nodetrace::tracer::cli
