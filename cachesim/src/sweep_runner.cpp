// run_sweep: the reader decodes on the calling thread while worker threads
// (formats' ordered pipeline) simulate, each its own part of the
// configurations, so decoding and simulation overlap.
#include <algorithm>
#include <exception>
#include <thread>

#include "nodetrace/cachesim/sweep.hpp"
#include "nodetrace/formats/ordered_pipeline.hpp"

namespace nodetrace::cachesim {

TraceResult run_sweep(formats::TraceReader& reader, const std::vector<NodeCacheConfig>& configs,
                      const std::string& trace_column, bool per_level,
                      const SweepProgress& progress, bool per_frame) {
  Sweep sweep(configs, trace_context(reader, trace_column), per_level, per_frame);
  const std::size_t cores = std::max(1u, std::thread::hardware_concurrency());
  // As many parts as cores (the reader's decoding threads share them): a
  // sweep with one unit of work (one configuration) stays one part, and
  // many configurations, whose simulation and not the decoding sets the
  // time (36 LRU configurations on a 75 M-record trace: about 5 s of
  // simulation CPU against about 1 s of decoding), use every core.
  sweep.set_parts(std::min<std::size_t>(cores, configs.size()));

  // Two batches: the workers simulate one (each its part of the
  // configurations) while the reader fills the other. A part's state runs
  // from batch to batch, so a batch's parts are submitted only once the
  // previous batch's are done.
  std::vector<formats::RecordBatch> batches(2);
  std::size_t current = 0;
  if (!reader.next(batches[current])) return sweep.finish();
  if (configs.size() == 1) {
    // One configuration: the reader's own workers decode ahead, so the
    // simulation runs here; a thread of its own would only add a hand-over
    // per batch.
    do {
      sweep.feed(batches[current]);
      if (progress) progress(batches[current].first_record + batches[current].records.size());
    } while (reader.next(batches[current]));
    return sweep.finish();
  }
  // The first batch starts the sweep, before any worker runs.
  sweep.begin_batch(batches[current]);
  formats::OrderedPipeline<void> simulation(static_cast<unsigned>(sweep.part_count()));
  const auto simulate = [&](std::size_t index) {
    for (std::size_t part = 0; part < sweep.part_count(); ++part) {
      simulation.submit([&sweep, &batch = batches[index], part] { sweep.feed_part(batch, part); });
    }
  };
  simulate(current);
  if (progress) progress(batches[current].first_record + batches[current].records.size());
  for (;;) {
    const std::size_t next = 1 - current;
    bool more = false;
    std::exception_ptr reader_error;
    try {
      more = reader.next(batches[next]);
    } catch (...) {
      reader_error = std::current_exception();
    }
    // A worker's error concerns earlier records than the reader's.
    while (!simulation.empty()) simulation.pop();
    if (reader_error) std::rethrow_exception(reader_error);
    if (!more) break;
    current = next;
    // Every batch advances K per animation frame here, in trace order.
    sweep.begin_batch(batches[current]);
    simulate(current);
    if (progress) progress(batches[current].first_record + batches[current].records.size());
  }
  return sweep.finish();
}

}  // namespace nodetrace::cachesim
