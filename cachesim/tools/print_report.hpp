// How cachesim run and dinero-wrap run print a report.
#pragma once

#include <cstdio>

#include "nodetrace/cachesim/simulation/simulation.hpp"

namespace nodetrace::cachesim::tools {

// `out` to standard output, `err` to standard error.
inline void print_report(const SimulationReport& report) {
  std::fwrite(report.out.data(), 1, report.out.size(), stdout);
  std::fflush(stdout);
  std::fwrite(report.err.data(), 1, report.err.size(), stderr);
}

}  // namespace nodetrace::cachesim::tools
