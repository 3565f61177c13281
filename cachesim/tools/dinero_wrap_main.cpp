// dinero-wrap: run Dinero IV on (compressed, container) traces.
//   dinero-wrap run TRACE... [cachesim run options] [--dinero CMD]
//   dinero-wrap exec TRACE [--dinero CMD] -- [dineroIV options]
#include <CLI/CLI.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <new>
#include <string_view>

#include "nodetrace/base/standard_output.hpp"
#include "nodetrace/cachesim/report/report.hpp"
#include "nodetrace/cachesim/wrap/wrap.hpp"
#include "nodetrace/base/error.hpp"
#include "nodetrace/cli/command_line.hpp"
#include "nodetrace/cli/exit_status.hpp"
#include "nodetrace/cli/option_limits.hpp"
#include "commands.hpp"
#include "nodetrace/cachesim/simulation/run_arguments.hpp"
#include "nodetrace/cachesim/simulation/simulation.hpp"
#include "print_report.hpp"
#include "nodetrace/cli/subcommand_dispatch.hpp"

namespace {

using namespace nodetrace;
using namespace nodetrace::cachesim;
namespace tools = nodetrace::cachesim::tools;

constexpr const char* kUsage =
    "dinero-wrap: answer cachesim questions with Dinero IV itself\n"
    "\n"
    "Usage:\n"
    "  dinero-wrap run TRACE... [options]        cachesim run's options and report, by Dinero IV\n"
    "  dinero-wrap exec TRACE [options] -- [dineroIV options]\n"
    "                                            feed one Dinero IV run, print its output\n"
    "  dinero-wrap --version                     the version, as trace headers record it\n"
    "\n"
    "Dinero IV is found by --dinero CMD, $DINEROIV, or dineroIV on PATH.\n"
    "`dinero-wrap SUBCOMMAND --help` describes each.\n";

int run_subcommand(int argc, char** argv) {
  SimulationOptions line;
  std::string dinero;
  unsigned jobs = 0;
  RunArgumentsSyntax syntax{
      "dinero-wrap run",
      "Answer `cachesim run` options with Dinero IV: one Dinero IV process per cache (at most "
      "one per core at a time), same report and columns as cachesim run."};
  syntax.cachesim_only_options = false;
  syntax.extra = {{"--dinero",
                   "Dinero IV command, may carry arguments (default: $DINEROIV, or dineroIV on "
                   "PATH)",
                   &dinero},
                  {"--jobs", "Dinero IV processes at a time (default: one per core; at most 16 per core)", &jobs}};
  if (const std::optional<int> status =
          parse_run_arguments(std::vector<std::string>(argv + std::min(argc, 1), argv + argc), syntax, line)) {
    return *status;
  }
  return cli::exit_status_of("dinero-wrap run", [&] {
    wrap::WrapOptions options;
    options.jobs = cli::check_thread_count(jobs, "--jobs", "processes");
    options.reader = reader_options(line);
    const SweepOptions sweep = sweep_options(line);
    for (const ReplacementPolicy policy : sweep.policies) {
      if (!dinero_has_policy(policy)) {
        throw base::UsageError(fmt::format(
            "--policy {}: Dinero IV has lru, fifo and random only; cachesim run simulates {}",
            policy_name(policy), policy_name(policy)));
      }
    }
    options.dinero = wrap::find_dinero(dinero.empty() ? std::nullopt
                                                      : std::optional<std::string>(dinero));
    std::vector<Configuration> configs = expand_configurations(sweep);
    std::vector<ResultRow> rows;
    std::vector<std::string> notes;
    if (const std::optional<std::string> split_size = split_size_note(line, sweep)) notes.push_back(*split_size);
    if (const std::optional<std::string> repeated = merge_repeated_configurations(configs)) notes.push_back(*repeated);
    for (const std::string& trace : line.traces) {
      TraceResult result = wrap::wrap_run(trace, configs, trace, sweep.per_level, options, sweep.per_animation_frame);
      rows.insert(rows.end(), result.rows.begin(), result.rows.end());
      notes.insert(notes.end(), result.notes.begin(), result.notes.end());
    }
    tools::print_report(sweep_report(rows, {}, notes, line));
    return 0;
  }, tools::kTooLarge);
}

int exec_subcommand(int argc, char** argv) {
  // Everything after `--` belongs to Dinero IV.
  int separator = argc;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--") == 0) {
      separator = i;
      break;
    }
  }
  std::vector<std::string> dinero_arguments(argv + std::min(separator + 1, argc), argv + argc);
  CLI::App app{
      "Decompress TRACE and feed its records to one Dinero IV run (adding -informat for the "
      "trace's record form unless given); Dinero IV's output is printed unchanged.",
      "dinero-wrap exec"};
  std::string trace;
  std::string dinero;
  std::string informat;
  app.add_option("trace", trace, "Trace file; - is standard input")->required();
  app.add_option("--dinero", dinero,
                 "Dinero IV command (default: $DINEROIV, or dineroIV on PATH)");
  app.add_option("--informat", informat, "Record form of a plain trace: din, xdin or binary")
      ->check(CLI::IsMember({"din", "xdin", "binary"}));
  app.footer("Example: dinero-wrap exec t.din.zst -- -l1-dsize 8k -l1-dbsize 8 -l1-dassoc 1");
  if (const std::optional<int> status = cli::parse_command_line(app, separator, argv)) return *status;
  return cli::exit_status_of("dinero-wrap exec", [&] {
    wrap::WrapOptions options;
    options.dinero = wrap::find_dinero(dinero.empty() ? std::nullopt
                                                      : std::optional<std::string>(dinero));
    if (!informat.empty()) options.reader.form = formats::parse_form_name(informat);
    const wrap::ExecResult result = wrap::wrap_exec(trace, dinero_arguments, options);
    // Written here rather than by Dinero IV into our output, so that an output
    // that cannot be written is seen (finish_standard_output: exit 1).
    std::fwrite(result.output.data(), 1, result.output.size(), stdout);
    return result.status;
  }, tools::kTooLarge);
}

}  // namespace

static int run(int argc, char** argv) {
  // A Dinero IV that quits early must give us EPIPE, not kill us.
  std::signal(SIGPIPE, SIG_IGN);
  return cli::dispatch_subcommand("dinero-wrap", kUsage, argc, argv,
                                  {{"run", run_subcommand}, {"exec", exec_subcommand}});
}

int main(int argc, char** argv) { return nodetrace::base::finish_standard_output("dinero-wrap", run(argc, argv)); }
