// The one parser of `cachesim run`'s command line: cachesim run, tracer
// render --simulate "OPTIONS" and dinero-wrap run (a subset) all read their
// options into SimulationOptions here, so each option has one spelling, one
// help text and one parse error.
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "nodetrace/cachesim/simulation/simulation_options.hpp"

namespace nodetrace::cachesim {

// An option of the front end's own beside cachesim run's (dinero-wrap run's --dinero).
struct ExtraOption {
  std::string name;  // "--dinero"
  std::string help;
  std::variant<std::string*, unsigned*> value;  // where the value goes
};

// Which of cachesim run's options a front end takes, and how it names itself.
struct RunArgumentsSyntax {
  RunArgumentsSyntax(std::string name_, std::string description_, bool traces_ = true)
      : name(std::move(name_)), description(std::move(description_)), traces(traces_) {}

  std::string name;         // "cachesim run": usage and errors say it
  std::string description;  // --help's first paragraph
  bool traces = true;       // trace files as positional arguments (required)
  // false: dinero-wrap run's subset, the options Dinero IV can answer (no
  // --per-level, --per-frame, --curve, sampling, units or second level).
  bool cachesim_only_options = true;
  std::vector<ExtraOption> extra;  // after cachesim run's, in --help
};

// Parses `arguments` (without the program's name) into `options`. Returns
// the exit status when parsing ends the run, after printing what it says:
// 0 for --help (usage on standard output), 2 for a parse error ("NAME: "
// and the message on standard error); nullopt when the run goes on. The
// options' values are checked by SimulationPlan, not here (except the
// fixed lists: --fetch, --informat, --units, --l2-policy, --format).
std::optional<int> parse_run_arguments(const std::vector<std::string>& arguments, const RunArgumentsSyntax& syntax,
                                       SimulationOptions& options);

}  // namespace nodetrace::cachesim
