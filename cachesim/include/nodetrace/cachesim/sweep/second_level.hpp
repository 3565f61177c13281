// A second-level cache shared by all traversal units (`cachesim run
// --l2-size/--l2-assoc/--l2-block`): for each configuration its first level
// (the single cache, or the split scheme's high and low caches; one copy per
// unit with private units) is simulated record by record, and every block
// it fetches from the next level (a miss, or a retained high cache's load:
// those blocks come from somewhere too) goes, in trace order, to the
// configuration's own L2 as one reference of one first-level block (address
// block x block size, size the block size): what Dinero IV simulates on a
// trace of those references.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "nodetrace/cachesim/models/cache_geometry.hpp"
#include "nodetrace/cachesim/report/result_row.hpp"
#include "nodetrace/cachesim/sweep/config.hpp"
#include "nodetrace/formats/read/trace_reader.hpp"

namespace nodetrace::cachesim {

// The first level's traffic as this simulator saw it, for the check against
// the sweep's counts (high_loads: a retained high cache's loads).
struct FirstLevelCounts {
  std::uint64_t high_misses = 0;
  std::uint64_t high_loads = 0;
  std::uint64_t low_misses = 0;  // the single cache's misses for `single`
};

class SecondLevelSimulator {
 public:
  // `units`: copies of each first level (1: shared by every unit). Throws
  // base::UsageError for a geometry that cannot be built, or a replacement
  // policy other than LRU and FIFO (random's draws are not the sweep's).
  SecondLevelSimulator(const std::vector<Configuration>& configs, const TraceContext& context, unsigned units,
                       const CacheGeometry& l2);
  ~SecondLevelSimulator();

  // Batches in trace order (markers included).
  void feed(const formats::RecordBatch& batch);
  // Per configuration, in order.
  std::vector<SecondLevelCounts> counts() const;
  std::vector<FirstLevelCounts> first_level_counts() const;

 private:
  struct FirstLevel;
  struct PerConfig;
  void begin_animation_frame(const formats::AnimationFrameMarker* marker);

  const std::vector<Configuration>& configs_;
  TraceContext context_;
  CacheGeometry l2_geometry_;
  unsigned units_ = 1;
  bool started_ = false;
  std::unique_ptr<SplitLevelPlan> plan_;
  std::vector<PerConfig> per_config_;
};

// Puts each configuration's L2 counts into its row, after checking that the
// simulator's first level saw what the sweep counted (throws
// std::logic_error naming the configuration when not).
void attach_second_level(std::vector<ResultRow>& rows, const SecondLevelSimulator& simulator);

}  // namespace nodetrace::cachesim
