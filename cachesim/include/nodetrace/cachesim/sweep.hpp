// One-pass sweeps: many node-cache configurations (DESIGN.md "Cache model")
// simulated together over one decode of a trace.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "nodetrace/cachesim/node_cache.hpp"
#include "nodetrace/formats/reader.hpp"
#include "nodetrace/formats/record.hpp"

namespace nodetrace::cachesim {

enum class Scheme : std::uint8_t { Single, Split };
enum class HighPolicy : std::uint8_t { Retain, Cache };

std::string_view scheme_name(Scheme scheme);           // single, split
std::optional<Scheme> parse_scheme_name(std::string_view name);
std::string_view high_policy_name(HighPolicy policy);  // retain, cache
std::optional<HighPolicy> parse_high_policy_name(std::string_view name);

// Associativity: a number, or "full" (returned as 0: all blocks of the cache).
std::uint32_t parse_assoc(std::string_view text);

// One configuration of the report, before K = auto is resolved.
struct NodeCacheConfig {
  Scheme scheme = Scheme::Single;
  std::uint64_t size = 8192;  // total: single cache, or high + low
  std::uint32_t block = 8;
  std::uint32_t assoc = 1;  // single / low cache ways (resolved, never 0)
  ReplacementPolicy policy = ReplacementPolicy::Lru;
  // Split scheme only.
  HighPolicy high_policy = HighPolicy::Retain;
  std::uint64_t high_size = 0;
  std::uint64_t low_size = 0;
  std::uint32_t high_assoc = 1;          // ways of the high cache under `cache`
  std::optional<std::uint32_t> split_level;  // nullopt: auto
  bool count_loads = false;              // retain: loads count as misses
};

// The command-line lists of `cachesim run` / `dinero-wrap run`.
struct SweepOptions {
  std::vector<std::uint64_t> sizes{8192};
  std::vector<std::uint32_t> blocks{8};
  std::vector<std::uint32_t> assocs{1};  // 0 = full
  std::vector<ReplacementPolicy> policies{ReplacementPolicy::Lru};
  std::vector<Scheme> schemes{Scheme::Single};
  std::vector<std::optional<std::uint32_t>> split_levels{std::nullopt};  // nullopt = auto
  std::vector<HighPolicy> high_policies{HighPolicy::Retain};
  std::optional<std::uint64_t> high_size;
  std::optional<std::uint64_t> low_size;
  std::optional<std::uint32_t> high_assoc;  // 0 = full; default: assoc
  bool count_loads = false;
  bool per_level = false;
};

// Every combination, in report order (size, block, assoc, policy, scheme,
// split level, high policy; innermost last). Validates each geometry; throws
// formats::UsageError.
std::vector<NodeCacheConfig> expand_configurations(const SweepOptions& options);

// Largest K for which all nodes of levels < K (nodes_per_level, node_size
// bytes each) fit in high_size bytes.
std::uint32_t auto_split_level(const std::vector<std::uint64_t>& nodes_per_level,
                               std::uint64_t node_size, std::uint64_t high_size);

// One report row (DESIGN.md column list). Optional fields are the empty
// columns (high / low columns of `single`, high_loads under `cache`).
struct ResultRow {
  std::string trace;
  NodeCacheConfig config;
  std::uint32_t split_level = 0;  // resolved K (split only)
  std::uint64_t refs = 0;
  std::uint64_t fetches = 0;
  std::uint64_t misses = 0;
  std::uint64_t high_refs = 0;
  std::uint64_t high_misses = 0;
  std::optional<std::uint64_t> high_loads;
  std::uint64_t low_refs = 0;
  std::uint64_t low_misses = 0;
};

// `--per-level`: references and misses of one node level in one configuration.
struct LevelRow {
  std::string trace;
  Scheme scheme = Scheme::Single;
  std::uint64_t size = 0;
  std::uint32_t level = 0;
  std::uint64_t refs = 0;
  std::uint64_t misses = 0;
};

struct TraceResult {
  std::vector<ResultRow> rows;
  std::vector<LevelRow> level_rows;
  std::uint64_t other_stream_records = 0;  // tagged p / t: counted, not simulated
  std::vector<std::string> notes;          // said under the table (or on stderr)
};

// What a sweep needs to know about its trace.
struct TraceContext {
  std::string trace;        // the report's `trace` column (argument as given)
  std::string source_name;  // for error messages
  formats::RecordForm form = formats::RecordForm::Din;
  bool tags_are_levels = false;
  std::optional<std::uint32_t> layout_split_level;  // header "layout"."split_level"
  std::uint64_t node_size = 8;                      // header "layout"."node_size"
};

// Fills a TraceContext from an opened reader.
TraceContext trace_context(const formats::TraceReader& reader, std::string trace_column);

// K of a split configuration: the one given, or auto from the first
// animation frame's marker (the one at the trace's first record; nullptr when
// there is none). Throws formats::UsageError for auto without nodes_per_level.
std::uint32_t resolve_split_level(const NodeCacheConfig& config,
                                  const formats::FrameMarker* first_marker,
                                  const TraceContext& context);
// The report's note when K differs from the header's layout split_level.
std::optional<std::string> split_level_note(const NodeCacheConfig& config,
                                            std::uint32_t split_level,
                                            const TraceContext& context);

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
  Sweep(std::vector<NodeCacheConfig> configs, TraceContext context, bool per_level);
  ~Sweep();
  Sweep(const Sweep&) = delete;
  Sweep& operator=(const Sweep&) = delete;

  // Throws formats::FormatError (untagged record where levels are needed) or
  // formats::UsageError (K = auto without markers; high levels that do not fit).
  void feed(const formats::RecordBatch& batch);
  TraceResult finish();

  // Work split over threads: before the first batch, set_parts(n) divides
  // the configurations into n parts of about equal cost. Then for each batch,
  // in trace order: begin_batch(batch) on one thread, then feed_part(batch, p)
  // for every part p, each part on one thread at a time (parts concurrently).
  // Together they equal feed(batch).
  void set_parts(std::size_t parts);
  std::size_t part_count() const;
  void begin_batch(const formats::RecordBatch& batch);
  void feed_part(const formats::RecordBatch& batch, std::size_t part);

 private:
  struct Part {
    std::vector<std::size_t> simulators;
    // The part's simulators in groups fed by one loop (see ConfigSimulator::
    // group_key); a group of one is fed alone.
    std::vector<std::vector<std::size_t>> groups;
    std::vector<ConfigSimulator*> group_members;  // scratch for feed_group
    PreparedBatch prepared;
    std::uint64_t other_stream_records = 0;
  };

  void start(const formats::RecordBatch& first_batch);
  // Fills part.prepared (and counts p / t records; throws for untagged ones).
  void prepare(const formats::Record* records, std::size_t count, std::uint64_t first_record,
               Part& part) const;

  std::vector<NodeCacheConfig> configs_;
  TraceContext context_;
  bool per_level_ = false;
  bool needs_levels_ = false;
  bool started_ = false;
  std::size_t requested_parts_ = 1;
  std::vector<Part> parts_;
  std::vector<std::unique_ptr<ConfigSimulator>> simulators_;
  std::vector<std::string> notes_;
};

// Called on the calling thread after each batch is read with the number of
// records read so far (for progress displays).
using SweepProgress = std::function<void(std::uint64_t records_read)>;

// Reads the whole trace once and simulates every configuration, decoding on
// the calling thread while worker threads (half the cores, at most one per
// configuration) simulate. Results do not depend on the number of threads.
TraceResult run_sweep(formats::TraceReader& reader, const std::vector<NodeCacheConfig>& configs,
                      const std::string& trace_column, bool per_level,
                      const SweepProgress& progress = {});

}  // namespace nodetrace::cachesim
