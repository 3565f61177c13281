// Opening an output by the one rule every program follows (docs/ARCHITECTURE.md
// "Conventions"): a regular file or a new name is written under a temporary
// name in the same folder and renamed into place when complete; a symbolic
// link is followed and its target replaced that way; a device, FIFO or socket
// (or an already open descriptor named as /dev/fd/N, /dev/stdout, ...) is
// written directly and never renamed over; "-" is standard output.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

namespace nodetrace::base {

enum class OutputMethod : std::uint8_t {
  StandardOutput,  // "-": file descriptor 1, left open
  Direct,          // written in place: devices, FIFOs, sockets, open descriptors
  Replace,         // a temporary in the target's folder, renamed over the target when complete
};

struct OutputPlan {
  OutputMethod method = OutputMethod::Replace;
  // Replace: the file that is replaced or created (symbolic links followed);
  // Direct: the path that is opened.
  std::string target;
  // Direct: the open descriptor a /dev/fd/N or /proc/self/fd/N path names
  // (written through a duplicate of it), or -1.
  int descriptor = -1;
  bool socket = false;  // Direct: a Unix socket, connected to rather than opened
};

// How `path` would be written, decided from what is there now; writes
// nothing. Throws IoError for a directory, a link loop or a path that cannot
// be examined.
OutputPlan plan_output(const std::string& path);

// The temporary name an output to `target` uses: `.NAME.tmp-PID-` followed by
// a unique suffix, in the target's folder.
std::string temporary_prefix(const std::string& target);

// Removes the temporaries of `target` left by processes that no longer run
// (a run killed by SIGKILL cannot remove its own); returns how many.
unsigned remove_stale_temporaries(const std::string& target);

// Throws the IoError that opening an OutputFile for `path` would throw (a
// missing folder, no permission, a directory), by creating and removing its
// temporary now: programs check every output before long work, so that a
// bad name fails at once instead of after the work. Devices, FIFOs, sockets
// and standard output are only examined (opening a FIFO would wait).
void check_output_writable(const std::string& path);

// One output, opened by plan_output's rule. Every failure throws IoError
// "NAME: cannot write: REASON" (NAME is the path as given, or "<stdout>").
// Until commit() succeeds, a replaced target is untouched; destroying the
// object (or a SIGINT, SIGTERM, SIGHUP or SIGPIPE, whose default action is
// kept) removes the temporary.
class OutputFile {
 public:
  explicit OutputFile(const std::string& path);
  ~OutputFile();
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;

  const std::string& name() const { return name_; }
  OutputMethod method() const { return plan_.method; }
  int descriptor() const { return fd_; }

  // Writes all of `bytes` (retrying short writes and EINTR).
  void write(std::string_view bytes);
  // Replace: fsync, close and rename over the target. Direct: close. The
  // standard output is left open.
  void commit();
  // Gives up: the temporary (if any) is removed; never throws.
  void abandon() noexcept;

 private:
  [[noreturn]] void fail(int error) const;

  std::string name_;
  OutputPlan plan_;
  int fd_ = -1;
  std::string temporary_;  // Replace: absolute path of the temporary, until renamed or removed
  int slot_ = -1;          // Replace: where the signal handler finds the temporary
  bool done_ = false;
};

}  // namespace nodetrace::base
