// Dinero IV's command line and output layout on top of the engine, so that
// `cachesim dinero` is a drop-in replacement for dineroIV.
#pragma once

#include <array>
#include <cstdint>
#include <iosfwd>
#include <string>
#include <vector>

#include "nodetrace/cachesim/dinero/engine.hpp"
#include "nodetrace/formats/read/trace_reader.hpp"
#include "nodetrace/formats/record/record.hpp"

namespace nodetrace::cachesim {

// Options as dineroIV takes them, after its defaults are filled in.
struct DineroOptions {
  enum class Request { Simulate, Help, Copyright, Contact, DineroIII };
  Request request = Request::Simulate;

  HierarchyConfig hierarchy;
  char informat = 'D';  // Dinero's default; d, D or b are supported
  bool informat_given = false;  // -informat was on the command line
  formats::RecordForm form = formats::RecordForm::ExtendedDin;
  bool stat_idcombine = false;
  std::string trace_path = "-";  // an extra positional argument; "-" is stdin

  // The -lN-T... values as Dinero holds them ([u,i,d][level-1]; 0 = unset),
  // kept to print its option summary.
  int max_level = 0;
  std::array<std::array<std::uint32_t, kMaxLevels>, 3> size{}, block_size{}, sub_block_size{},
      assoc{}, prefetch_distance{}, prefetch_abort{};
  std::array<std::array<char, kMaxLevels>, 3> replacement{}, fetch{}, write_allocate{},
      write_back{};
  std::array<std::array<bool, kMaxLevels>, 3> ccc{};
  std::uint64_t skip_count = 0, flush_count = 0, max_count = 0, stat_interval = 0;
  std::uint64_t on_trigger = 0, off_trigger = 0;
};

// Parses dineroIV arguments (without the program name). Throws
// base::UsageError naming the offending option, with Dinero's wording
// where Dinero has one; unsupported options (-custom, input formats other
// than d, D, b) are errors that name them.
DineroOptions parse_dinero_options(const std::vector<std::string>& args);

// A container names its own record form: without -informat, `options`
// takes it (and the summary prints its letter); with a -informat naming
// another form, throws base::UsageError. Plain input is left as it is.
void match_trace_form(DineroOptions& options, const formats::TraceReader& reader);

// `message` (a trace error) with Dinero IV's advice to try -informat d when
// extended din input had an unknown access type.
std::string with_informat_hint(const DineroOptions& options, const std::string& message);

// The banner and "---Summary of options" block, exactly as dineroIV prints it.
std::string dinero_preamble(const DineroOptions& options);

// The per-cache metrics tables for every level, as Dinero's dostats().
std::string dinero_statistics(const Hierarchy& hierarchy, const DineroOptions& options);

// Runs a whole dineroIV session over `reader`: writes to `out` exactly what
// dineroIV writes to standard output, and Dinero's warnings to `warnings`.
// Throws base::FormatError (naming the record) on bad trace data.
void run_dinero(const DineroOptions& options, formats::TraceReader& reader, std::ostream& out,
                std::ostream& warnings);

// Help text for `cachesim dinero --help`.
std::string dinero_help();

}  // namespace nodetrace::cachesim
