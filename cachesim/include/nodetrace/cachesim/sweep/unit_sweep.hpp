// Private node caches per traversal unit (`cachesim run --units private`):
// each unit of a trace whose records carry units (header "units") gets its
// own copy of every configured cache, fed that unit's records in trace
// order. The report's rows are the sums over the units; the per-unit rows
// (`--per-unit FILE`) are a table of their own. A second-level cache shared
// by the units (`--l2-size`) is simulated in the same pass, with private or
// shared first levels.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "nodetrace/cachesim/models/cache_geometry.hpp"
#include "nodetrace/cachesim/report/result_row.hpp"
#include "nodetrace/cachesim/sweep/sweep.hpp"
#include "nodetrace/formats/read/trace_reader.hpp"

namespace nodetrace::cachesim {

struct UnitSweepResult {
  // One row per configuration: counts summed over the units (its K, resolved
  // from the same markers, is every unit's).
  TraceResult total;
  // Configurations in report order within each unit, units in order.
  std::vector<UnitRow> unit_rows;
};

struct UnitSweepOptions {
  // Each unit its own caches (reader.units() of them; a trace without units
  // is one unit); false: one copy shared by every unit (no unit rows).
  bool private_units = true;
  // A second-level cache shared by the units (second_level.hpp): each row
  // then carries its counts.
  std::optional<CacheGeometry> l2;
};

// Simulates every configuration once per unit in one pass over the trace,
// the units on worker threads. The counts do not depend on the thread count.
UnitSweepResult run_unit_sweep(formats::TraceReader& reader, const std::vector<Configuration>& configs,
                               const std::string& trace_column, const UnitSweepOptions& options,
                               const SweepProgress& progress = {});

}  // namespace nodetrace::cachesim
