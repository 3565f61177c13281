// The one mapping from errors to exit codes of every front end: 2 for bad
// usage (base::UsageError), 1 for anything else (bad data, I/O, Dinero IV
// failing, memory). The message goes to standard error after `command: `,
// once what was already printed to standard output is flushed.
#pragma once

#include <cstdio>
#include <exception>
#include <iostream>
#include <new>
#include <string>

#include "nodetrace/base/error.hpp"

namespace nodetrace::cli {

// Prints "COMMAND: MESSAGE" on standard error after flushing standard output.
inline void report_error(const char* command, const char* message) {
  std::cout.flush();
  std::fflush(stdout);
  std::fprintf(stderr, "%s: %s\n", command, message);
}

// Runs `body` (which returns the exit status) and maps what it throws.
// `too_large` names what runs out of memory ("the scene or image"): the
// message then says it is too large for this machine.
template <typename Body>
int exit_status_of(const char* command, Body body, const char* too_large = nullptr) {
  try {
    return body();
  } catch (const base::UsageError& error) {
    report_error(command, error.what());
    return 2;
  } catch (const std::bad_alloc&) {
    const std::string message = too_large == nullptr
                                    ? std::string("out of memory")
                                    : std::string("out of memory (") + too_large + " too large for this machine)";
    report_error(command, message.c_str());
    return 1;
  } catch (const std::exception& error) {
    report_error(command, error.what());
    return 1;
  }
}

}  // namespace nodetrace::cli
