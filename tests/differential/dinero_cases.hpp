// The differential test against the real Dinero IV: a seeded generator of
// traces and of dineroIV command lines, and the comparison of Dinero IV's
// whole output with `cachesim dinero`'s for each. Shared by the GoogleTest
// (tests/cachesim/test_dinero_differential.cpp, a fixed seed range) and the
// dinero_diff program behind scripts/dinero-diff.sh (any number of cases).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace nodetrace::testing {

// One case: a trace in the form -informat names, and the arguments.
struct DineroCase {
  std::uint64_t seed = 0;
  std::vector<std::string> args;  // dineroIV arguments, -informat included
  std::string trace;              // the bytes fed on standard input
  std::string trace_name;         // trace.din, trace.xdin or trace.bin
};

// The case of `seed`: the same seed gives the same case on every host.
DineroCase make_dinero_case(std::uint64_t seed);

struct DineroComparison {
  // Dinero IV accepted the arguments and the trace (exit 0). Cases it
  // rejects are not compared configurations; `cachesim dinero` must reject
  // them too (same == true then means it did).
  bool valid = false;
  // Dinero IV crashed (a signal) or ran past its time limit (5 s): its own
  // faults (the generator leaves out the configurations known to cause them,
  // caches of 32 sub-blocks per block). Not compared.
  bool dinero_broke = false;
  bool same = false;  // standard output byte for byte, and the warnings
  int dinero_status = -1, cachesim_status = -1;
  std::string dinero_out, dinero_err, cachesim_out, cachesim_err;
};

// Runs `dinero` and `cachesim dinero` on the case (trace on standard input,
// written under `work`) and compares them. Warnings are compared after the
// program name that starts them.
DineroComparison compare_dinero_case(const DineroCase& c, const std::filesystem::path& dinero,
                                     const std::filesystem::path& cachesim,
                                     const std::filesystem::path& work);

// Writes the case into `folder` (created): the trace, `args` (one line, as
// given to both programs), `dinero.out` / `.err`, `cachesim.out` / `.err`,
// and `status` (both exit statuses).
void keep_dinero_case(const DineroCase& c, const DineroComparison& result,
                      const std::filesystem::path& folder);

// The arguments as one shell-quoted line.
std::string joined_arguments(const std::vector<std::string>& args);

}  // namespace nodetrace::testing
