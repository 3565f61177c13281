// tracer render --simulate "CACHESIM RUN OPTIONS" --report FILE: cachesim
// run's simulation of each layout's records in this process, fed by a
// record sink per layout through a formats::RecordPipe (no text), on a
// thread per layout while the render goes on. The options are parsed and
// checked by cachesim run's own parser and
// checks (cachesim's simulation API), and the report is the one cachesim
// run prints for the container traces the render would write. A library of
// its own (the tracer library never includes cachesim): `tracer render` and
// the Python module's render(simulate=...) share it.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "nodetrace/cachesim/simulation/simulation.hpp"
#include "nodetrace/cli/distinct_outputs.hpp"
#include "nodetrace/tracer/render/record_sink.hpp"
#include "nodetrace/tracer/render/trace_job.hpp"

namespace nodetrace::tracer::simulate {

// One --simulate "[LAYOUT=]OPTIONS" of a render.
class InRenderSimulation {
 public:
  ~InRenderSimulation();
  // Parses and checks `text` as cachesim run does (errors say
  // "tracer render --simulate: " and cachesim's message); the exit status
  // when they end the run (a bad option, --help), else nullopt. A text
  // "LAYOUT=OPTIONS" simulates that layout only (a name of `layout_names`,
  // the {layout} names of the render's layouts); else every layout.
  std::optional<int> parse(const std::string& text, const std::vector<std::string>& layout_names);
  // The options as already-split words (every layout): parsed by cachesim
  // run's parser under the same name, its error printed; the exit status
  // when they end the run, else nullopt with `options` set.
  static std::optional<int> parse_words(const std::vector<std::string>& words, cachesim::SimulationOptions& options);
  // Simulates every layout with options already parsed; throws the
  // simulation plan's error (base::UsageError) for options it refuses.
  void plan(cachesim::SimulationOptions options);
  // The sinks' maker; `trace_names[i]`: layout i's trace column (its file,
  // or its {layout} name when none is written). What the simulation sees is
  // the container trace of each layout, whatever form -o writes.
  RecordSinkMaker sink_maker(std::vector<std::string> trace_names);
  // The files its options' own tables go to (--per-level FILE ...; not "-",
  // which is the report's), each named "--simulate's OPTION".
  std::vector<cli::NamedOutput> table_files() const;
  // After the job: the report of every layout, in order.
  cachesim::SimulationReport report() const;

  // The trace column of each layout's simulation: its trace file in
  // `options`, or its {layout} name (`layout_names[i]`) when none is written.
  static std::vector<std::string> trace_names(const TraceJobOptions& options,
                                              const std::vector<std::string>& layout_names);

  // One layout's simulation (its sink's and the report's).
  struct Layout;

 private:
  std::optional<std::size_t> only_layout_;
  std::optional<cachesim::SimulationPlan> plan_;
  std::optional<cachesim::SimulationMode> mode_;
  std::vector<std::shared_ptr<Layout>> layouts_;
};

}  // namespace nodetrace::tracer::simulate
