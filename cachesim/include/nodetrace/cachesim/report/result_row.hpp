// What a run answers, per trace: the report's rows (one per configuration),
// and the per-level and per-animation-frame rows. The sweep, the sampled
// sweep and the Dinero IV wrapper fill them; the report prints them.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "nodetrace/cachesim/sweep/config.hpp"

namespace nodetrace::cachesim {

// A second-level cache's counts for one configuration (`--l2-size`): its
// geometry, the first-level fetches it saw (refs), its demand fetches and
// misses.
struct SecondLevelCounts {
  std::uint64_t size = 0;
  std::uint32_t block = 0;
  std::uint32_t assoc = 0;
  std::uint64_t refs = 0;
  std::uint64_t fetches = 0;
  std::uint64_t misses = 0;
};

// One report row (DESIGN.md column list). Optional fields are the empty
// columns (high / low columns of `single`, high_loads under `cache`).
struct ResultRow {
  std::string trace;
  Configuration config;
  std::uint32_t split_level = 0;  // resolved K (split only)
  std::uint64_t refs = 0;
  std::uint64_t fetches = 0;
  std::uint64_t misses = 0;
  std::uint64_t high_refs = 0;
  std::uint64_t high_misses = 0;
  std::optional<std::uint64_t> high_loads;
  std::uint64_t low_refs = 0;
  std::uint64_t low_misses = 0;
  // Runs with a second-level cache only: its own columns after low_misses.
  std::optional<SecondLevelCounts> l2;
  // Runs with --prefetch only: the prefetch columns, last.
  std::optional<PrefetchColumns> prefetch;
};

// `--per-level`: references and misses of one node level in one configuration
// (every configuration column, so rows of configurations of the same scheme
// and size stay apart).
struct LevelRow {
  std::string trace;
  Configuration config;
  std::uint32_t split_level = 0;  // resolved K (split only): the sweep sets it as its row's
  std::uint32_t level = 0;
  std::uint64_t refs = 0;
  std::uint64_t misses = 0;
};

// `--per-frame`: one configuration's counts in one animation frame (its
// split_level is that frame's K).
struct AnimationFrameRow {
  std::uint64_t frame = 0;
  ResultRow row;
};

// `--per-unit`: one configuration's counts in one traversal unit's private
// caches (`cachesim run --units private`).
struct UnitRow {
  unsigned unit = 0;
  ResultRow row;
};

struct TraceResult {
  std::vector<ResultRow> rows;
  std::vector<LevelRow> level_rows;
  std::vector<AnimationFrameRow> animation_frame_rows;  // frame by frame, configurations in report order
  std::uint64_t other_stream_records = 0;  // tagged p / t: counted, not simulated
  std::vector<std::string> notes;          // said under the table (or on stderr)
};

}  // namespace nodetrace::cachesim
