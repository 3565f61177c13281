// `cachesim dinero`: dineroIV's command line and output over the engine.
#include <cstdio>
#include <exception>
#include <iostream>
#include <string>
#include <vector>

#include "commands.hpp"
#include "nodetrace/cli/exit_status.hpp"
#include "nodetrace/cachesim/dinero/command_line.hpp"
#include "nodetrace/base/error.hpp"
#include "nodetrace/formats/read/trace_reader.hpp"

namespace nodetrace::cachesim::tools {

namespace {

// Dinero IV's own table, byte for byte (its spelling "DineroIV" included).
constexpr const char* kDineroIII =
    "Summary of DineroIV replacements for DineroIII options:\n\n"
    "DineroIII    DineroIV\n"
    "-u           -l1-usize\n"
    "-i           -l1-isize\n"
    "-d           -l1-dsize\n"
    "-b           -l1-ubsize, -l1-ibsize, or -l1-dbsize\n"
    "-S           -l1-usbsize, -l1-isbsize, or -l1-dsbsize\n"
    "-a           -l1-uassoc, -l1-iassoc, or -l1-dassoc\n"
    "-r           -l1-urepl, -l1-irepl, or -l1-drepl\n"
    "-f           -l1-ufetch, -l1-ifetch, or -l1-dfetch\n"
    "-p           -l1-upfdist, -l1-ipfdist, or -l1-dpfdist\n"
    "-P           -l1-upfabort, -l1-ipfabort, or -l1-dpfabort\n"
    "-w           -l1-uwback or -l1-dwback\n"
    "-A           -l1-uwalloc or -l1-dwalloc\n"
    "-Q           -flushcount\n"
    "-z           -maxcount\n"
    "-Z           -skipcount\n"
    "\n"
    "DineroIII input format: -informat d\n";

constexpr const char* kAbout =
    "cachesim dinero reimplements the behaviour of Dinero IV (Jan Edler and Mark D. Hill;\n"
    "Copyright (C) 1997 NEC Research Institute, Inc. and Mark D. Hill) for comparison;\n"
    "it contains none of Dinero IV's code.\n";

}  // namespace

int dinero_command(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  return nodetrace::cli::exit_status_of("cachesim dinero", [&] {
    DineroOptions options;
    try {
      options = parse_dinero_options(args);
    } catch (const base::UsageError& e) {
      throw base::UsageError(std::string(e.what()) +
                             "\nRun \"cachesim dinero --help\" for usage information.");
    }
    switch (options.request) {
      case DineroOptions::Request::Help: std::fputs(dinero_help().c_str(), stdout); return 0;
      case DineroOptions::Request::DineroIII: std::fputs(kDineroIII, stdout); return 0;
      case DineroOptions::Request::Copyright:
      case DineroOptions::Request::Contact: std::fputs(kAbout, stdout); return 0;
      case DineroOptions::Request::Simulate: break;
    }
    formats::ReaderOptions reader_options;
    reader_options.form = options.form;
    reader_options.allow_empty = true;  // as dineroIV, which reads an empty input as a trace
    reader_options.binary_form_option = "-informat b";
    auto reader = formats::TraceReader::open(options.trace_path, reader_options);
    match_trace_form(options, *reader);
    std::ios::sync_with_stdio(false);
    run_dinero(options, *reader, std::cout, std::cerr);
    std::cout.flush();
    return 0;
  }, kTooLarge);
}

}  // namespace nodetrace::cachesim::tools
