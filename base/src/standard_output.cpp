#include "nodetrace/base/standard_output.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <cstring>
#include <iostream>

#include <unistd.h>

#include "nodetrace/base/error.hpp"

namespace nodetrace::base {

namespace {
// Errors only a write gives: when one is still in errno as a failed stream is
// found, it is almost surely that write's reason.
bool is_write_error(int error) {
  return error == ENOSPC || error == EPIPE || error == EIO || error == EDQUOT || error == EFBIG || error == EBADF;
}
}  // namespace

std::optional<std::string> flush_standard_output() {
  const int pending = errno;
  errno = 0;
  std::cout.flush();
  int error = std::cout.fail() ? errno : 0;
  const bool cout_failed = std::cout.bad();
  errno = 0;
  if (std::fflush(stdout) != 0 && error == 0) error = errno;
  if (!cout_failed && !std::ferror(stdout) && error == 0) return std::nullopt;
  // A write that failed before (its error flag is sticky) may have left its
  // reason in errno; the C library keeps no other record of it.
  if (error == 0 && is_write_error(pending)) error = pending;
  const std::string reason = error != 0 ? std::strerror(error) : "an earlier write failed";
  return fmt::format("<stdout>: cannot write: {}", reason);
}

void refuse_binary_on_terminal(const std::string& path, const std::string& what) {
  if (path == "-" && ::isatty(STDOUT_FILENO)) {
    throw UsageError(fmt::format("refusing to write {} to a terminal; redirect standard output", what));
  }
}

}  // namespace nodetrace::base
