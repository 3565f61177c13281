// The one mapping from errors to exit codes of the cachesim front ends
// (cachesim run, cachesim dinero, dinero-wrap): 2 for bad usage
// (formats::UsageError), 1 for anything else (bad data, I/O, Dinero IV
// failing, memory). The message goes to standard error after `command: `,
// once what was already printed to standard output is flushed.
#pragma once

#include <cstdio>
#include <exception>
#include <iostream>
#include <new>
#include <stdexcept>

#include "nodetrace/formats/error.hpp"

namespace nodetrace::cachesim::cli {

template <typename Body>
int exit_status_of(const char* command, Body body) {
  auto report = [command](const std::exception& error) {
    std::cout.flush();
    std::fflush(stdout);
    std::fprintf(stderr, "%s: %s\n", command, error.what());
  };
  try {
    return body();
  } catch (const formats::UsageError& error) {
    report(error);
    return 2;
  } catch (const std::bad_alloc&) {
    report(std::runtime_error("out of memory (the caches or trace frames are too large for this machine)"));
    return 1;
  } catch (const std::exception& error) {
    report(error);
    return 1;
  }
}

}  // namespace nodetrace::cachesim::cli
