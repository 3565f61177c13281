// run_sweep: the reader decodes on the calling thread while worker threads
// (formats' ordered pipeline) simulate, each its own part of the
// configurations, so decoding and simulation overlap.
#include <algorithm>
#include <exception>
#include <thread>

#include "nodetrace/cachesim/sweep/sweep.hpp"
#include "nodetrace/base/ordered_pipeline.hpp"

namespace nodetrace::cachesim {

namespace {

TraceResult simulate_sweep(formats::TraceReader& reader, const std::vector<Configuration>& configs,
                           const std::string& trace_column, bool per_level, const SweepProgress& progress,
                           bool per_animation_frame) {
  Sweep sweep(configs, trace_context(reader, trace_column), per_level, per_animation_frame);
  const std::size_t cores = std::max(1u, std::thread::hardware_concurrency());
  // As many parts as cores (the reader's decoding threads share them): a
  // sweep with one unit of work (one configuration) stays one part, and
  // many configurations, whose simulation and not the decoding sets the
  // time (36 LRU configurations on a 75 M-record trace: about 5 s of
  // simulation CPU against about 1 s of decoding), use every core.
  sweep.set_parts(std::min<std::size_t>(cores, configs.size()));

  formats::RecordBatch first;
  if (!reader.next(first)) return sweep.finish();
  if (configs.size() == 1) {
    // One configuration: the reader's own workers decode ahead, so the
    // simulation runs here; a thread of its own would only add a hand-over
    // per batch.
    do {
      sweep.feed(first);
      if (progress) progress(first.first_record + first.records.size());
    } while (reader.next(first));
    return sweep.finish();
  }
  // Two groups of batches: the workers simulate one (each its part of the
  // configurations) while the reader fills the other. A part's state runs
  // from group to group, so a group's parts are submitted only once the
  // previous group's are done. A group holds up to kGroupRecords records: a
  // container hands over a data frame in pieces of 16K records, and one
  // hand-over per piece cost the 36-configuration sweep a quarter more time.
  constexpr std::size_t kGroupRecords = std::size_t{1} << 18;
  struct Group {
    std::vector<formats::RecordBatch> batches;
    std::size_t size = 0;  // batches in use
  };
  std::vector<Group> groups(2);
  bool ended = false;
  // Reads batches into `group` from its batch `from` on; false when it has none.
  const auto fill = [&](Group& group, std::size_t from) {
    group.size = from;
    std::size_t records = 0;
    for (std::size_t i = 0; i < from; ++i) records += group.batches[i].records.size();
    while (!ended && records < kGroupRecords) {
      if (group.size == group.batches.size()) group.batches.emplace_back();
      if (!reader.next(group.batches[group.size])) {
        ended = true;
        break;
      }
      records += group.batches[group.size++].records.size();
    }
    return group.size > 0;
  };
  // Every batch advances K per animation frame here, in trace order; the
  // first starts the sweep, before any worker runs.
  const auto begin = [&](Group& group) {
    for (std::size_t i = 0; i < group.size; ++i) sweep.begin_batch(group.batches[i]);
  };
  groups[0].batches.push_back(std::move(first));
  fill(groups[0], 1);
  begin(groups[0]);
  base::OrderedPipeline<void> simulation(static_cast<unsigned>(sweep.part_count()));
  const auto simulate = [&](Group& group) {
    for (std::size_t part = 0; part < sweep.part_count(); ++part) {
      simulation.submit([&sweep, &group, part] {
        for (std::size_t i = 0; i < group.size; ++i) sweep.feed_part(group.batches[i], part);
      });
    }
    if (progress) {
      const formats::RecordBatch& last = group.batches[group.size - 1];
      progress(last.first_record + last.records.size());
    }
  };
  simulate(groups[0]);
  std::size_t current = 0;
  for (;;) {
    const std::size_t next = 1 - current;
    bool more = false;
    std::exception_ptr reader_error;
    try {
      more = fill(groups[next], 0);
    } catch (...) {
      reader_error = std::current_exception();
    }
    // A worker's error concerns earlier records than the reader's.
    while (!simulation.empty()) simulation.pop();
    if (reader_error) std::rethrow_exception(reader_error);
    if (!more) break;
    current = next;
    begin(groups[current]);
    simulate(groups[current]);
  }
  return sweep.finish();
}

}  // namespace

TraceResult run_sweep(formats::TraceReader& reader, const std::vector<Configuration>& configs,
                      const std::string& trace_column, bool per_level,
                      const SweepProgress& progress, bool per_animation_frame) {
  TraceResult result = simulate_sweep(reader, configs, trace_column, per_level, progress, per_animation_frame);
  // Bytes per ray: the trailer, read by now, says the rays.
  if (has_treelet_prefetch(configs)) {
    const std::optional<std::uint64_t> rays = trace_rays(reader);
    for (ResultRow& row : result.rows) {
      if (row.prefetch) row.prefetch->rays = rays;
    }
  }
  return result;
}

}  // namespace nodetrace::cachesim
