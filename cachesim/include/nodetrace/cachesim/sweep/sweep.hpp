// One-pass sweeps: many node-cache configurations (docs/ARCHITECTURE.md "Cache model")
// simulated together over one decode of a trace.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "nodetrace/cachesim/report/result_row.hpp"
#include "nodetrace/formats/read/trace_reader.hpp"
#include "nodetrace/formats/record/record.hpp"

namespace nodetrace::cachesim {

class ConfigSimulator;

// What the configurations' fast paths need to know of a chunk of records,
// found once for all of them.
struct PreparedBatch {
  // Every record is a demand fetch (read, write, instruction, misc) of a
  // node (no p / t records).
  bool demand_only = false;
  // OR over the records (as Dinero IV simulates them) of first byte ^ last
  // byte: blocks larger than this hold every record whole (one fetch each).
  std::uint64_t span_bits = 0;
};

// Simulates every configuration over batches fed in trace order.
class Sweep {
 public:
  Sweep(std::vector<Configuration> configs, TraceContext context, bool per_level,
        bool per_animation_frame = false);
  ~Sweep();
  Sweep(const Sweep&) = delete;
  Sweep& operator=(const Sweep&) = delete;

  // Throws base::FormatError (untagged record where levels are needed) or
  // base::UsageError (K = auto without markers; high levels that do not fit).
  // K is resolved per animation frame, from each frame's marker.
  void feed(const formats::RecordBatch& batch);
  TraceResult finish();
  // Each configuration's totals so far, in report order (sampled runs take
  // differences at window boundaries). Only between batches, while no
  // feed_part runs; empty before the first batch.
  std::vector<ResultRow> counts() const;

  // Work split over threads: before the first batch, set_parts(n) divides
  // the configurations into at most n parts (a stack group cut into pieces
  // where it alone is more than a part's share). Then for each batch, in
  // trace order: begin_batch(batch) on one thread, then feed_part(batch, p)
  // for every part p, each part on one thread at a time (parts concurrently).
  // Together they equal feed(batch). begin_batch may run for several batches
  // before their feed_part calls, in trace order, while no feed_part runs. Parts start of about equal estimated
  // cost; begin_batch shares the units out anew now and then by the CPU
  // time each took so far (which only moves work between threads: the
  // counts are the same whatever the parts).
  void set_parts(std::size_t parts);
  std::size_t part_count() const;
  void begin_batch(const formats::RecordBatch& batch);
  void feed_part(const formats::RecordBatch& batch, std::size_t part);

 private:
  // Simulators fed by one loop: a stack group or a piece of one, or a
  // policy grid (fed through its first member, for all of them) with the
  // stack group of its block size that walks what its filters kept, a set
  // of split configurations fed together, or one configuration.
  struct WorkUnit {
    std::vector<std::size_t> simulators;  // in report order
    std::vector<std::size_t> leaders;     // the ones fed, in this order (each feeds its group)
    double estimate = 0;   // work per record, estimated (stack_group.hpp's units)
    double seconds = 0;    // CPU time of its feeds so far (only its part's thread writes it)
  };
  struct Part {
    std::vector<std::size_t> units;
    std::vector<std::size_t> simulators;  // of its units, in order
    PreparedBatch prepared;
    std::uint64_t other_stream_records = 0;
  };
  // One configuration's animation frame in progress (per_animation_frame).
  struct OpenAnimationFrame {
    bool open = false;
    std::uint64_t frame = 0;
    std::uint32_t split_level = 0;
    ResultRow at_start;  // the totals when it began
  };

  void start(const formats::RecordBatch& first_batch);
  // Units to parts, greedily, the costliest first (by `cost` of each unit).
  void assign_parts(const std::vector<double>& cost);
  // The simulator's frame ends (per_animation_frame: its row is kept) and, with a
  // marker, the next begins with that frame's K.
  void change_frame(std::size_t simulator, const formats::AnimationFrameMarker* marker);
  // Fills part.prepared (and counts p / t records; throws for untagged ones).
  // `known`: what the reader found every record of the batch to be
  // (RecordBatch::kinds).
  void prepare(const formats::Record* records, std::size_t count, std::uint64_t first_record,
               formats::RecordKinds known, Part& part) const;

  std::vector<Configuration> configs_;
  TraceContext context_;
  bool per_level_ = false;
  bool per_animation_frame_ = false;
  bool needs_levels_ = false;
  bool one_byte_blocks_ = false;  // then every batch is checked for block number 2^64 - 1
  bool prefetching_ = false;      // a --fetch other than demand: Dinero IV's engine, 32-bit addresses
  // --prefetch treelet: configs_ holds the reported configurations, then
  // those without the prefetcher that are not among them (for coverage);
  // without_prefetch_[c] is where reported configuration c's is.
  bool treelet_prefetch_ = false;
  std::size_t reported_ = 0;
  std::vector<std::size_t> without_prefetch_;
  bool started_ = false;
  std::size_t requested_parts_ = 1;
  std::vector<WorkUnit> units_;
  std::vector<Part> parts_;
  std::uint64_t batches_ = 0;  // begun so far (the units are shared out anew at powers of two)
  std::vector<std::unique_ptr<ConfigSimulator>> simulators_;
  std::unique_ptr<SplitLevelPlan> plan_;  // advanced by begin_batch, in trace order
  std::vector<OpenAnimationFrame> open_frames_;                // per simulator, its part's thread
  std::vector<std::vector<AnimationFrameRow>> animation_frame_rows_;     // per simulator
};

// Called on the calling thread after each batch is read with the number of
// records read so far (for progress displays).
using SweepProgress = std::function<void(std::uint64_t records_read)>;

// Reads the whole trace once and simulates every configuration, decoding on
// the calling thread while worker threads (one per core, at most one per
// unit of work: sweep parts) simulate. Results do not depend on the number of threads.
TraceResult run_sweep(formats::TraceReader& reader, const std::vector<Configuration>& configs,
                      const std::string& trace_column, bool per_level,
                      const SweepProgress& progress = {}, bool per_animation_frame = false);

}  // namespace nodetrace::cachesim
