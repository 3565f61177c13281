// dinero-wrap: answering `cachesim run` questions with Dinero IV itself.
// Each cache a configuration needs is one Dinero IV process fed the records
// (din / extended din text) on a pipe; its output is parsed back into the
// same report rows as `cachesim run` prints.
#pragma once

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "nodetrace/cachesim/report/result_row.hpp"
#include "nodetrace/formats/read/trace_reader.hpp"

namespace nodetrace::cachesim::wrap {

// Dinero IV could not be started, failed, or printed what we cannot read.
class WrapError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Splits a command into words at blanks; '...' and "..." group words, no
// other shell syntax (nothing is ever given to a shell). Throws
// base::UsageError for an unterminated quote.
std::vector<std::string> split_command(std::string_view command);

// The Dinero IV command: `option` (--dinero) if given, else $DINEROIV, else
// `dineroIV` found on PATH. Throws base::UsageError saying how to point at
// one when none is found.
std::vector<std::string> find_dinero(const std::optional<std::string>& option);

// One cache table of Dinero IV's output.
struct DineroCacheStats {
  std::string name;  // e.g. "l1-ucache"
  std::uint64_t demand_fetches = 0;  // Total column
  std::uint64_t demand_misses = 0;
};

// Reads the "Demand Fetches" and "Demand Misses" rows of every cache table.
// Throws base::FormatError when there is no cache table or a row is
// missing or unreadable.
std::vector<DineroCacheStats> parse_dinero_output(std::string_view output);

// A running child process with its standard input on a pipe.
class ChildProcess {
 public:
  // What becomes of the child's standard output and error: both captured
  // (readable after wait()), or output captured and errors passed straight
  // to ours (so Dinero IV's own messages reach the user as it prints them).
  enum class Output { Captured, ErrorsInherited };

  // Starts argv (argv[0] searched on PATH) with stdin from a pipe.
  ChildProcess(const std::vector<std::string>& argv, Output output);
  ~ChildProcess();  // kills and reaps a child still running
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  // Writes all of `bytes` to the child's stdin. Returns false, writing no
  // more, once the child has closed its input (it exited, or stopped reading
  // as Dinero IV does at -maxcount): wait() then says how it ended. Needs
  // SIGPIPE ignored, as the front end does. Throws WrapError on other errors.
  bool write(std::string_view bytes);
  // Closes stdin and waits; returns the exit status (128 + signal if killed).
  int wait();
  const std::string& output() const { return output_; }
  const std::string& errors() const { return errors_; }
  const std::string& command() const { return command_; }

 private:
  int pid_ = -1;
  int stdin_fd_ = -1;
  int stdout_fd_ = -1;  // temporary files, read back by wait()
  int stderr_fd_ = -1;
  std::string output_;
  std::string errors_;
  std::string command_;
};

struct WrapOptions {
  std::vector<std::string> dinero;  // the Dinero IV command
  unsigned jobs = 0;                // Dinero IV processes at a time; 0 = one per core
  formats::ReaderOptions reader;
};

// The Dinero IV arguments of a cache: -informat, -l1-usize, -l1-ubsize,
// -l1-uassoc, -l1-urepl, and -l1-ufetch, -l1-upfdist unless demand fetch.
std::vector<std::string> dinero_cache_arguments(formats::RecordForm form,
                                                const CacheGeometry& geometry,
                                                FetchPolicy fetch = FetchPolicy::Demand,
                                                std::uint32_t prefetch_distance = 1);

// `cachesim run` answered by Dinero IV for the trace at `path`: read once per
// group of at most `jobs` processes ("-", standard input, is read once, so
// then every process runs in that one pass). K is resolved per animation
// frame as `cachesim run` does. Throws base::UsageError for --per-level and
// --per-frame, WrapError, base::FormatError / IoError.
TraceResult wrap_run(const std::string& path, const std::vector<Configuration>& configs,
                     const std::string& trace_column, bool per_level, const WrapOptions& options,
                     bool per_animation_frame = false);

// Feeds the trace's records to one Dinero IV run with `arguments` (adding
// -informat for the trace's form unless given; when given, the records are
// written in the form it names: din or extended din text, or binary
// records). Dinero IV's errors go straight to our standard error; its
// output and exit status are returned, also when it stopped reading early
// (-maxcount, or an option it rejected), for the caller to print unchanged.
struct ExecResult {
  int status = 0;
  std::string output;
};
ExecResult wrap_exec(const std::string& path, const std::vector<std::string>& arguments,
                     const WrapOptions& options);

}  // namespace nodetrace::cachesim::wrap
