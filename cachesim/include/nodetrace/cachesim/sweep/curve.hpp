// `cachesim run --curve`: miss ratio against cache size, every power-of-two
// size from one set to max_size, for the given block sizes and
// associativities, of single caches and of the low cache of the split
// scheme, in one pass over the trace. Fully associative LRU sizes come from
// one Mattson stack (lru_stack.hpp), fully associative MIN (opt) sizes from
// MIN's layered stack over the fetches kept in memory (opt_curve.hpp);
// set-associative sizes from the sweep (set stacks for LRU and direct-mapped
// caches, one simulation each for the other policies), opt's from one MIN
// simulation per size over the same kept fetches.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "nodetrace/cachesim/report/report.hpp"
#include "nodetrace/cachesim/sweep/config.hpp"
#include "nodetrace/formats/read/trace_reader.hpp"

namespace nodetrace::cachesim {

struct CurveOptions {
  std::vector<std::uint32_t> blocks{8};
  std::vector<std::uint32_t> assocs{1};  // 0 = full (lru and opt only)
  std::vector<Scheme> schemes{Scheme::Single};
  std::vector<ReplacementPolicy> policies{ReplacementPolicy::Lru};
  std::optional<std::uint32_t> split_level;  // nullopt: auto for high_size
  std::optional<std::uint64_t> high_size;    // needed by auto
  std::uint64_t max_size = std::uint64_t{64} << 20;
};

// One point: for split, `size`, `fetches` and `misses` are the low cache's.
struct CurvePoint {
  std::string trace;
  Scheme scheme = Scheme::Single;
  std::uint32_t block = 8;
  std::uint32_t assoc = 1;  // 0 = full
  ReplacementPolicy policy = ReplacementPolicy::Lru;
  std::uint32_t split_level = 0;  // split: the first animation frame's K
  std::uint64_t size = 0;
  std::uint64_t fetches = 0;
  std::uint64_t misses = 0;
};

// Throws base::UsageError for options it cannot answer, and as run_sweep.
std::vector<CurvePoint> run_curve(formats::TraceReader& reader, const CurveOptions& options,
                                  const std::string& trace_column);

// Removes every point that is the same cache as an earlier one: the same
// trace, scheme, policy, block and size and the same `assoc` label (a one-set cache
// of N ways is the fully associative one, so `--assoc 4,full` meet at the
// 4-block size; a value listed twice repeats a whole curve). The note says
// how many were merged (nullopt: none).
std::optional<std::string> merge_repeated_points(std::vector<CurvePoint>& points);

// Columns trace,scheme,block,assoc,policy,split_level,size,fetches,misses,miss_ratio
// as a table, CSV or JSON (report.hpp's shapes).
std::string format_curve(const std::vector<CurvePoint>& points, ReportFormat format);

}  // namespace nodetrace::cachesim
