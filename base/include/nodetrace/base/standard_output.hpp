// The last check of a program's standard output: reports (tables, CSV,
// --help) go through C stdio or iostreams, whose buffered writes fail only
// when flushed, often at exit where nobody looks. Every front end ends with
// finish_standard_output, so a lost report is an error (exit 1), not silence.
#pragma once

#include <cstdio>
#include <optional>
#include <string>

namespace nodetrace::base {

// Flushes std::cout and C's stdout; returns "<stdout>: cannot write: REASON"
// when that or any earlier write to them failed, else nullopt.
std::optional<std::string> flush_standard_output();

// Throws UsageError when `path` is "-" and standard output is a terminal:
// compressed or binary bytes there are noise that can upset the terminal.
// `what` names the output ("a trace", "binary records").
void refuse_binary_on_terminal(const std::string& path, const std::string& what);

// For a front end's main(): `return finish_standard_output("tracer", status);`.
// Prints the error as "PROGRAM: <stdout>: cannot write: REASON" and makes a
// successful status 1; a run that failed already said why and keeps its status.
inline int finish_standard_output(const char* program, int status) {
  const std::optional<std::string> error = flush_standard_output();
  if (!error || status != 0) return status;
  std::fprintf(stderr, "%s: %s\n", program, error->c_str());
  return status == 0 ? 1 : status;
}

}  // namespace nodetrace::base
