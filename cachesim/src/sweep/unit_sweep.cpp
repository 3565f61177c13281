// run_unit_sweep: the trace read in groups of batches, each group split by
// unit, then every unit's sweep fed its part on the workers (a unit's caches
// are its own: units never share state, so they run concurrently).
#include "nodetrace/cachesim/sweep/unit_sweep.hpp"

#include <algorithm>
#include <memory>
#include <thread>

#include "nodetrace/base/ordered_pipeline.hpp"
#include "nodetrace/cachesim/sweep/second_level.hpp"

namespace nodetrace::cachesim {

namespace {

ResultRow& add_counts(ResultRow& sum, const ResultRow& unit) {
  sum.refs += unit.refs;
  sum.fetches += unit.fetches;
  sum.misses += unit.misses;
  sum.high_refs += unit.high_refs;
  sum.high_misses += unit.high_misses;
  if (unit.high_loads) sum.high_loads = sum.high_loads.value_or(0) + *unit.high_loads;
  sum.low_refs += unit.low_refs;
  sum.low_misses += unit.low_misses;
  return sum;
}

}  // namespace

UnitSweepResult run_unit_sweep(formats::TraceReader& reader, const std::vector<Configuration>& configs,
                               const std::string& trace_column, const UnitSweepOptions& options,
                               const SweepProgress& progress) {
  const unsigned units = options.private_units ? reader.units() : 1;
  const TraceContext context = trace_context(reader, trace_column);
  std::optional<SecondLevelSimulator> second_level;
  if (options.l2) second_level.emplace(configs, context, units, *options.l2);
  std::vector<std::unique_ptr<Sweep>> sweeps;
  for (unsigned u = 0; u < units; ++u) sweeps.push_back(std::make_unique<Sweep>(configs, context, false));
  // Each unit's batches of a group; a unit's first_record counts its own
  // records (what its sweep's errors name).
  std::vector<std::vector<formats::RecordBatch>> group(units);
  std::vector<std::uint64_t> unit_records(units, 0);
  const unsigned threads = std::max(1u, std::min(units, std::thread::hardware_concurrency()));
  base::OrderedPipeline<void> workers(threads);
  std::vector<formats::RecordBatch> whole;  // the group's batches as read, for the second level
  const auto simulate = [&] {
    for (unsigned u = 0; u < units; ++u) {
      workers.submit([&, u] {
        for (const formats::RecordBatch& batch : group[u]) sweeps[u]->feed(batch);
      });
    }
    // The second level after the first levels' sweeps: they stop the run
    // first on what a first level cannot hold (a retained high cache that
    // overflows).
    while (!workers.empty()) workers.pop();
    if (second_level) {
      for (const formats::RecordBatch& batch : whole) second_level->feed(batch);
    }
    whole.clear();
    for (auto& batches : group) batches.clear();
  };
  constexpr std::size_t kGroupRecords = std::size_t{1} << 18;
  std::size_t grouped = 0;
  formats::RecordBatch batch;
  while (reader.next(batch)) {
    for (unsigned u = 0; u < units; ++u) {
      formats::RecordBatch& part = group[u].emplace_back();
      part.marker = batch.marker;
      part.window = batch.window;
      part.first_record = unit_records[u];
    }
    if (units == 1) {
      group[0].back().records = batch.records;
    } else {
      for (const formats::Record& record : batch.records) {
        group[formats::unit_index(record.unit)].back().records.push_back(record);
      }
    }
    for (unsigned u = 0; u < units; ++u) unit_records[u] += group[u].back().records.size();
    if (second_level) whole.push_back(batch);
    grouped += batch.records.size();
    if (grouped >= kGroupRecords) {
      simulate();
      grouped = 0;
      if (progress) progress(batch.first_record + batch.records.size());
    }
  }
  simulate();
  UnitSweepResult result;
  for (unsigned u = 0; u < units; ++u) {
    TraceResult unit = sweeps[u]->finish();
    if (u == 0) {
      result.total = unit;
    } else {
      for (std::size_t i = 0; i < unit.rows.size(); ++i) add_counts(result.total.rows[i], unit.rows[i]);
      result.total.other_stream_records += unit.other_stream_records;
      for (const std::string& note : unit.notes) {
        if (std::find(result.total.notes.begin(), result.total.notes.end(), note) == result.total.notes.end()) {
          result.total.notes.push_back(note);
        }
      }
    }
    if (options.private_units) {
      for (const ResultRow& row : unit.rows) result.unit_rows.push_back({u, row});
    }
  }
  if (second_level) attach_second_level(result.total.rows, *second_level);
  return result;
}

}  // namespace nodetrace::cachesim
