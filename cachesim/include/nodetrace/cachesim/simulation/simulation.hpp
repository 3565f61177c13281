// cachesim's simulation API: what `cachesim run`, `tracer render --simulate`
// and the Python module run, so all take one vocabulary, raise one set of
// errors and print one report.
//
//   SimulationOptions options;                  // or parse_run_arguments
//   options.sizes = {"4k", "8k"};
//   options.format = "csv";
//   const SimulationPlan plan(options);         // every check before a trace is read
//   auto reader = formats::TraceReader::open(path, plan.reader_options());
//   const SimulationMode mode = plan.mode_for({reader.get()});
//   std::vector<TraceOutcome> outcomes{plan.simulate(mode, *reader, path)};
//   SimulationReport report = plan.report(mode, outcomes);  // report.out: the CSV
//
// Or fed batch by batch on the caller's thread (the records of a render):
//   std::unique_ptr<Simulation> fed = plan.start(mode, *reader, path);
//   fed->feed(batch); ...; outcomes.push_back(fed->finish());
//
// Errors: base::UsageError (a command line's exit 2) naming the option, with
// cachesim run's messages; anything else about the data (exit 1).
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "nodetrace/cachesim/sampling/sampled_sweep.hpp"
#include "nodetrace/cachesim/sweep/curve.hpp"
#include "nodetrace/cachesim/sweep/sweep.hpp"
#include "nodetrace/cachesim/sweep/unit_sweep.hpp"
#include "nodetrace/cachesim/simulation/simulation_options.hpp"
#include "nodetrace/formats/read/trace_reader.hpp"

namespace nodetrace::cachesim {

// How a run simulates its traces: decided by the options, and by whether
// some trace is row-sampled.
enum class SimulationMode { Sweep, Curve, UnitCaches, Sampled };

// What one trace gives, in the mode's form.
struct TraceOutcome {
  TraceResult sweep;                // Sweep; UnitCaches: the units' sums
  std::vector<UnitRow> unit_rows;   // UnitCaches
  std::vector<CurvePoint> curve;    // Curve
  SampledResult sampled;            // Sampled
};

// What a run prints: `out` on standard output (or the file a caller
// chooses), `err` (the notes of CSV and JSON) on standard error.
struct SimulationReport {
  std::string out, err;
};

// One trace's simulation fed its record batches in trace order, on the
// caller's thread (SimulationPlan::start).
class Simulation {
 public:
  virtual ~Simulation() = default;
  virtual void feed(const formats::RecordBatch& batch) = 0;
  // After the last batch: the trace's outcome.
  virtual TraceOutcome finish() = 0;
};

// Options checked, in the engine's form: built once per run, then used for
// each of its traces.
class SimulationPlan {
 public:
  // Every check of cachesim run before a trace is read: throws
  // base::UsageError with its messages.
  explicit SimulationPlan(SimulationOptions options);

  const SimulationOptions& options() const { return line_; }
  // How to open the traces (--informat, --threads, window sampling).
  formats::ReaderOptions reader_options() const;
  // The mode for these traces (all of a run's, opened before any is read),
  // with the checks that depend on them.
  SimulationMode mode_for(const std::vector<const formats::TraceReader*>& readers) const;
  // Simulates one trace read whole; `trace_column` names it in the report.
  TraceOutcome simulate(SimulationMode mode, formats::TraceReader& reader, const std::string& trace_column,
                        const SweepProgress& progress = {}) const;
  // The simulation of one trace fed its batches: what simulate() gives for
  // a reader of the same batches. `source` gives the trace's header and
  // form (its records are not read). Null for the modes that read a trace
  // their own way (--curve, private caches of units): simulate() those.
  std::unique_ptr<Simulation> start(SimulationMode mode, const formats::TraceReader& source,
                                    const std::string& trace_column) const;
  // The report of the traces' outcomes, in order; writes the side tables
  // that name files (--per-level, --per-frame, --per-unit).
  SimulationReport report(SimulationMode mode, const std::vector<TraceOutcome>& outcomes) const;

 private:
  // States (a note) and checks (base::UsageError) the memory of the caches' state.
  void check_state_memory();

  SimulationOptions line_;
  SweepOptions options_;
  SamplingOptions sampling_;
  std::vector<Configuration> configs_;
  // The note that repeated configurations were merged, first of the report's.
  std::vector<std::string> configuration_notes_;
  UnitSweepOptions unit_options_;
};

// The report of a sweep's rows (dinero-wrap run's too): the main table,
// the side tables the options name, and the notes.
SimulationReport sweep_report(const std::vector<ResultRow>& rows, const std::vector<LevelRow>& levels,
                              const std::vector<std::string>& notes, const SimulationOptions& options,
                              const std::vector<AnimationFrameRow>& frames = {},
                              const std::vector<UnitRow>& unit_rows = {});

}  // namespace nodetrace::cachesim
