// What a call writes on standard error (file descriptor 2), taken instead
// of shown: the command-line parser of cachesim run's options prints its
// parse error ("NAME: MESSAGE") rather than throwing it, and Python wants the
// message in the exception.
#pragma once

#include <unistd.h>

#include <cstdio>
#include <string>

#include "nodetrace/base/error.hpp"

namespace nodetrace::python {

template <typename Call>
auto capture_stderr(std::string& captured, Call call) -> decltype(call()) {
  std::fflush(stderr);
  std::FILE* file = std::tmpfile();
  if (file == nullptr) throw base::IoError("cannot make a temporary file for the option parser's messages");
  const int saved = ::dup(2);
  ::dup2(::fileno(file), 2);
  struct Restore {
    int saved;
    std::FILE* file;
    std::string& captured;
    ~Restore() {
      std::fflush(stderr);
      ::dup2(saved, 2);
      ::close(saved);
      std::rewind(file);
      char buffer[4096];
      for (std::size_t got; (got = std::fread(buffer, 1, sizeof buffer, file)) > 0;) captured.append(buffer, got);
      std::fclose(file);
    }
  } restore{saved, file, captured};
  return call();
}

}  // namespace nodetrace::python
