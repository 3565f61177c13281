// cachesim run: single and split node caches, every combination of the
// listed options simulated in one pass over each trace.
#include <memory>
#include <optional>
#include <algorithm>
#include <string>
#include <utility>
#include <vector>

#include "commands.hpp"
#include "nodetrace/cachesim/simulation/run_arguments.hpp"
#include "nodetrace/cachesim/simulation/simulation.hpp"
#include "nodetrace/cli/exit_status.hpp"
#include "nodetrace/cli/progress_line.hpp"
#include "nodetrace/formats/read/trace_reader.hpp"
#include "print_report.hpp"

namespace nodetrace::cachesim::tools {

namespace {

// The records a trace holds, when its trailer says (a seekable container).
std::optional<std::uint64_t> record_total(const formats::TraceReader& reader) {
  const auto& trailer = reader.trailer();
  if (!trailer || !trailer->totals.contains("records") || !trailer->totals["records"].is_number_unsigned()) {
    return std::nullopt;
  }
  return trailer->totals["records"].get<std::uint64_t>();
}

}  // namespace

int run_command(int argc, char** argv) {
  const RunArgumentsSyntax syntax{
      "cachesim run",
      "Simulate single and split node caches on traces; every combination of the listed values "
      "is simulated in one pass over each trace.\n"
      "Example: cachesim run t.din.zst --size 4k,8k,16k --scheme single,split --format csv"};
  SimulationOptions options;
  if (const std::optional<int> status =
          parse_run_arguments(std::vector<std::string>(argv + std::min(argc, 1), argv + argc), syntax, options)) {
    return *status;
  }
  return nodetrace::cli::exit_status_of("cachesim run", [&] {
    const SimulationPlan plan(std::move(options));
    // Every trace opened before any is read: whether one is row-sampled
    // decides the report's columns.
    const std::vector<std::string>& traces = plan.options().traces;
    std::vector<std::unique_ptr<formats::TraceReader>> readers;
    std::vector<const formats::TraceReader*> opened;
    for (const std::string& trace : traces) {
      readers.push_back(formats::TraceReader::open(trace, plan.reader_options()));
      opened.push_back(readers.back().get());
    }
    const SimulationMode mode = plan.mode_for(opened);
    nodetrace::cli::ProgressLine progress_line;
    std::vector<TraceOutcome> outcomes;
    for (std::size_t t = 0; t < readers.size(); ++t) {
      SweepProgress progress;
      if (progress_line.shown() && mode == SimulationMode::Sweep) {
        const std::optional<std::uint64_t> total = record_total(*readers[t]);
        progress = [&, total](std::uint64_t records_read) {
          progress_line.update_count(traces[t], records_read, total, "records");
        };
        progress_line.restart();
      }
      outcomes.push_back(plan.simulate(mode, *readers[t], traces[t], progress));
      progress_line.clear();
    }
    print_report(plan.report(mode, outcomes));
    return 0;
  }, kTooLarge);
}

}  // namespace nodetrace::cachesim::tools
