// Every option of `cachesim run` as one plain struct: what a front end
// (cachesim run, tracer render --simulate, dinero-wrap run, Python) fills in,
// from a command line (parse_run_arguments) or field by field, before
// SimulationPlan checks it. Defaults are cachesim run's.
//
// Values a message quotes back are kept as written ("8k", "full", "auto"),
// so that an error names the option and the value as the user typed them;
// SimulationPlan turns them into the engine's types (SweepOptions ...).
//
// Adding an option: a field here, its flag in run_arguments.cpp, its check
// and use in simulation_options.cpp (sweep_options) or simulation.cpp.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "nodetrace/cachesim/sampling/sampled_sweep.hpp"
#include "nodetrace/cachesim/sweep/sweep.hpp"
#include "nodetrace/formats/read/trace_reader.hpp"

namespace nodetrace::cachesim {

// The largest cache a run simulates (--size, --high-size, --low-size,
// --l2-size): the simulator allocates its blocks' state up front, so the
// limit bounds the memory of each cache whatever the trace's length; the
// run's total is stated and checked before it starts (SimulationPlan).
inline constexpr std::uint64_t kMaxCacheBytes = std::uint64_t{256} << 20;
// And the most blocks one cache holds (256m of 8-byte blocks), so small
// blocks cannot multiply that memory.
inline constexpr std::uint64_t kMaxCacheBlocks = kMaxCacheBytes / 8;

struct SimulationOptions {
  // Trace files (cachesim run's positional arguments; "-" is standard
  // input). Empty where the caller feeds the records itself.
  std::vector<std::string> traces;
  // The lists: every combination is one configuration.
  std::vector<std::string> sizes{"8k"};    // --size, bytes with optional k/m
  bool sizes_given = false;                // --size given, not its default (a split's note says so)
  std::vector<std::string> blocks{"8"};    // --block
  std::vector<std::string> assocs{"1"};    // --assoc: ways or "full"
  std::vector<std::string> policies{"lru"};       // --policy (kPolicyNames)
  std::vector<std::string> schemes{"single"};     // --scheme: single, split
  std::vector<std::string> split_levels{"auto"};  // --split-level: K or "auto"
  std::vector<std::string> high_policies{"retain"};  // --high-policy: retain, cache
  bool high_policies_given = false;                  // --high-policy given (not with --curve)
  std::string high_size;   // --high-size ("" = half the total)
  std::string low_size;    // --low-size ("" = the rest)
  std::string high_assoc;  // --high-assoc ("" = --assoc)
  bool count_loads = false;           // --count-loads
  std::string fetch = "demand";       // --fetch: demand, always, miss, tagged, load-forward, subblock
  unsigned prefetch_distance = 1;     // --prefetch-distance
  // Traversal units and the second-level cache.
  std::optional<std::string> units;   // --units: shared (the default) or private
  std::string l2_size;                // --l2-size ("" = no second level)
  std::optional<std::uint32_t> l2_block;   // --l2-block (default 64)
  std::optional<std::string> l2_assoc;     // --l2-assoc (default "8")
  std::optional<std::string> l2_policy;    // --l2-policy: lru (default) or fifo
  // --prefetch (list): none, treelet[:BYTES], treelet-low[:BYTES] (empty: not given).
  std::vector<std::string> prefetch;
  // Side tables: the file each goes to ("" = none, "-" = the report's own output).
  std::string per_level;   // --per-level
  std::string per_frame;   // --per-frame
  std::string per_unit;    // --per-unit (--units private)
  bool curve = false;      // --curve: the miss ratio of every power-of-two size instead
  // Sampling.
  std::string sample_windows;  // --sample-windows K ("" = none)
  std::string sample_sets;     // --sample-sets K ("" = none)
  std::uint64_t window_records = kDefaultWindowRecords;  // --window-records
  std::uint64_t sample_seed = 0;                         // --sample-seed
  // Reading and reporting.
  std::string format = "table";  // --format: table, csv, json
  std::string informat;          // --informat: din, xdin, binary ("" = detected)
  bool tags_are_levels = false;  // --tags-are-levels
  unsigned threads = 0;          // --threads: decoding threads, 0 = one per core

  const std::string& units_or_default() const {
    static const std::string shared = "shared";
    return units ? *units : shared;
  }
};

// The checks of the options that describe caches (--size ... --per-frame),
// and the engine's form of them: throws base::UsageError naming the option.
SweepOptions sweep_options(const SimulationOptions& options);
// How the traces are read (--informat, --tags-are-levels, --threads).
formats::ReaderOptions reader_options(const SimulationOptions& options);
// With --high-size and --low-size both given the split cache is their sum,
// whatever --size says: the note that says so where a --size given differs.
std::optional<std::string> split_size_note(const SimulationOptions& options, const SweepOptions& sweep);

}  // namespace nodetrace::cachesim
