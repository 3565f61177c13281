// Errors thrown by the formats library. Libraries never print or exit; front
// ends catch these and map them to exit codes (1 for bad data).
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>

namespace nodetrace::base {

// Bad or damaged trace data. what() names the source (file name or "<stdin>")
// and, where one applies, the 1-based record number, and says what was
// expected, e.g. "t.din: record 12: non hex digit (code 0x67) in address".
class FormatError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A file that cannot be opened, read or written.
class IoError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// An option or combination of options that cannot work (exit code 2 in CLIs).
class UsageError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

}  // namespace nodetrace::base
