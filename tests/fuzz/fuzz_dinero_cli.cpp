// The Dinero IV command line of `cachesim dinero`: one argument per line.
// Options that parse are printed as Dinero's summary and, when the caches
// are small, simulated on a fixed trace.
#include <sstream>
#include <vector>

#include "fuzz_support.hpp"
#include "nodetrace/cachesim/dinero/command_line.hpp"
#include "nodetrace/base/error.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  namespace formats = nodetrace::formats;
  std::vector<std::string> args;
  std::string current;
  for (const char c : nodetrace::fuzz::as_text(data, size)) {
    if (c == '\n') {
      args.push_back(current);
      current.clear();
    } else {
      current += c;
    }
  }
  if (!current.empty()) args.push_back(current);
  nodetrace::cachesim::DineroOptions options;
  try {
    options = nodetrace::cachesim::parse_dinero_options(args);
  } catch (const nodetrace::base::UsageError&) {
    return 0;
  }
  (void)nodetrace::cachesim::dinero_preamble(options);
  if (options.request != nodetrace::cachesim::DineroOptions::Request::Simulate) return 0;
  std::uint64_t bytes = 0;
  for (const auto& kind : options.size) {
    for (const auto value : kind) bytes += value;
  }
  if (bytes > (1u << 20)) return 0;  // large caches cost time, not coverage
  static const std::string trace = [] {
    std::string text;
    for (unsigned i = 0; i < 2000; ++i) {
      text += "rwim"[i % 4];
      text += ' ';
      text += std::to_string((i * 2654435761u) % 65536 * 4);
      text += " 4\n";
    }
    return text;
  }();
  const nodetrace::fuzz::MemoryFile file(trace);
  formats::ReaderOptions reader_options;
  reader_options.form = formats::RecordForm::ExtendedDin;
  reader_options.threads = 1;
  try {
    auto reader = formats::TraceReader::open(file.path(), reader_options);
    std::ostringstream out, warnings;
    nodetrace::cachesim::run_dinero(options, *reader, out, warnings);
  } catch (const nodetrace::base::UsageError&) {
  } catch (const nodetrace::base::FormatError&) {
  }
  return 0;
}
