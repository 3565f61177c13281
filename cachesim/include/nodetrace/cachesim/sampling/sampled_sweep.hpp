// Sampled runs of `cachesim run` (cachesim/SAMPLING.md): simulate one window
// of the trace in every K, or the blocks of one cache set in every K, and
// report each configuration's miss ratio and the split gain with their error.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "nodetrace/cachesim/sampling/sampling_estimate.hpp"
#include "nodetrace/cachesim/sweep/sweep.hpp"
#include "nodetrace/formats/read/trace_reader.hpp"

namespace nodetrace::cachesim {

// One container data frame by default (formats::WriterOptions), so that a
// skipped window is a skipped data frame; see SAMPLING.md for the measurement.
inline constexpr std::uint64_t kDefaultWindowRecords = std::uint64_t{1} << 20;
// The most set groups simulated apart to measure the spread between sets.
inline constexpr std::uint64_t kMaxSetGroups = 8;

struct SamplingOptions {
  std::uint64_t window_every = 0;  // K of --sample-windows 1/K; 0: every record
  std::uint64_t window_records = kDefaultWindowRecords;
  std::uint64_t set_every = 0;     // K of --sample-sets 1/K; 0: every set
  std::uint64_t seed = 0;
  bool sampling() const { return window_every != 0 || set_every != 0; }
};


// Which window (0 .. every - 1) of a stratum of `every` consecutive windows
// is simulated: a hash of (seed, stratum), so any offset is equally likely.
std::uint64_t chosen_in_stratum(std::uint64_t seed, std::uint64_t stratum, std::uint64_t every);

// Whether `options` simulates window `window`, and any record of
// [first, first + count).
bool window_chosen(const SamplingOptions& options, std::uint64_t window);
bool records_chosen(const SamplingOptions& options, std::uint64_t first, std::uint64_t count);

// The reader's keep_data_frame for these options: container data frames
// with no record in a chosen window are never decompressed.
std::function<bool(const formats::DataFrameIndexEntry&)> data_frame_filter(const SamplingOptions& options);

struct SampledRow {
  ResultRow row;                  // the counts simulated; miss_ratio is the estimate
  double sampled_fraction = 0;    // records simulated / records in the trace
  Estimate estimate;
};

// The split gain of one split configuration: single minus split miss ratio
// against the single configuration of the same size, block, assoc and policy.
struct GainRow {
  ResultRow split;
  ResultRow single;
  double sampled_fraction = 0;
  Estimate estimate;
};

struct SampledResult {
  std::vector<SampledRow> rows;  // report order
  std::vector<GainRow> gains;    // in the order of the split rows
  std::vector<std::string> notes;
  std::uint64_t windows = 0;          // in the trace
  std::uint64_t windows_simulated = 0;
};

// Throws base::UsageError for set sampling that cannot be done (a cache
// with fewer than K sets, a set count that is not a power of two, several
// block sizes) and as run_sweep.
SampledResult run_sampled_sweep(formats::TraceReader& reader,
                                const std::vector<Configuration>& configs,
                                const std::string& trace_column, const SamplingOptions& options);

// run_sampled_sweep fed its batches in trace order on the caller's thread
// instead of reading them (in-render simulation); `source` gives the
// trace's header, and its trailer at finish(). Throws as run_sampled_sweep.
class FedSampledSweep {
 public:
  FedSampledSweep(const formats::TraceReader& source, const std::vector<Configuration>& configs,
                  const std::string& trace_column, const SamplingOptions& options);
  ~FedSampledSweep();
  FedSampledSweep(const FedSampledSweep&) = delete;
  FedSampledSweep& operator=(const FedSampledSweep&) = delete;
  void feed(const formats::RecordBatch& batch);
  SampledResult finish();

 private:
  class Run;
  const formats::TraceReader& source_;
  std::unique_ptr<Run> run_;
};

}  // namespace nodetrace::cachesim
