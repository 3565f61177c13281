// `cachesim run` in parts another front end can drive (tracer render
// --simulate): its options, their checks before any trace is read, the
// simulation of one trace, and the report of several. One vocabulary, one
// set of errors, one report, whoever gives the traces.
#pragma once

#include <CLI/CLI.hpp>

#include <memory>
#include <string>
#include <vector>

#include "nodetrace/cachesim/sampling/sampled_sweep.hpp"
#include "nodetrace/cachesim/sweep/curve.hpp"
#include "nodetrace/cachesim/sweep/sweep.hpp"
#include "nodetrace/cachesim/sweep/unit_sweep.hpp"
#include "nodetrace/formats/read/trace_reader.hpp"
#include "run_options.hpp"

namespace nodetrace::cachesim::tools {

// The second-level cache of `cachesim run --l2-size`.
struct SecondLevelCommandLine {
  std::string size;
  std::uint32_t block = 64;
  std::string assoc = "8";
  std::string policy = "lru";
};

// The sampling options of `cachesim run` (dinero-wrap has none).
struct SamplingCommandLine {
  std::string windows;
  std::string sets;
  std::uint64_t window_records = kDefaultWindowRecords;
  std::uint64_t seed = 0;
};

// How a run simulates its traces: decided by the options, and by whether
// some trace is row-sampled.
enum class RunMode { Sweep, Curve, UnitCaches, Sampled };

// What one trace gives, in the mode's form.
struct TraceOutcome {
  TraceResult sweep;                // Sweep; UnitCaches: the units' sums
  std::vector<UnitRow> unit_rows;   // UnitCaches
  std::vector<CurvePoint> curve;    // Curve
  SampledResult sampled;            // Sampled
};

// One trace's simulation fed batch by batch, in trace order (RunSession::fed_simulation).
class FedSimulation {
 public:
  virtual ~FedSimulation() = default;
  virtual void feed(const formats::RecordBatch& batch) = 0;
  virtual TraceOutcome finish() = 0;
};

class RunSession {
 public:
  // `traces_positional`: cachesim run names its traces on the command line;
  // a caller that makes its own readers takes none.
  void add_options(CLI::App& app, bool traces_positional = true);
  // The checks of the options alone, before any trace is read: throws
  // base::UsageError as cachesim run does.
  void prepare(const CLI::App& app);
  const RunCommandLine& line() const { return line_; }
  formats::ReaderOptions reader_options() const;
  // The mode for these traces (all of a run's, opened before any is read),
  // with the checks that depend on them.
  RunMode mode_for(const std::vector<const formats::TraceReader*>& readers) const;
  // Simulates one trace; `trace_column` names it in the report.
  TraceOutcome simulate(RunMode mode, formats::TraceReader& reader, const std::string& trace_column,
                        const SweepProgress& progress = {}) const;
  // The simulation of one trace fed its batches on the caller's thread:
  // what simulate() gives for a reader of the same batches, with no thread
  // of its own. `source` gives the trace's header and form (its records are
  // not read). Null for the modes that read a trace their own way (--curve,
  // private caches of units).
  std::unique_ptr<FedSimulation> fed_simulation(RunMode mode, const formats::TraceReader& source,
                                                const std::string& trace_column) const;
  // The report of the traces' outcomes, in order; writes the side tables
  // that name files (--per-level, --per-frame, --per-unit).
  RunReport report(RunMode mode, const std::vector<TraceOutcome>& outcomes) const;

 private:
  // States (a note) and checks (base::UsageError) the memory of the caches' state.
  void check_state_memory();

  RunCommandLine line_;
  SamplingCommandLine sampling_line_;
  SecondLevelCommandLine l2_line_;
  std::vector<std::string> prefetch_line_;  // --prefetch, as given
  SweepOptions options_;
  SamplingOptions sampling_;
  std::vector<Configuration> configs_;
  // The note that repeated configurations were merged, first of the report's.
  std::vector<std::string> configuration_notes_;
  UnitSweepOptions unit_options_;
};

}  // namespace nodetrace::cachesim::tools
