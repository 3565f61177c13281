// One configuration's simulator, as the sweep drives it: fed chunks of
// records in trace order, told where animation frames begin, asked for its
// counts. The sweep (sweep.cpp) partitions, routes batches and keeps the
// per-frame rows; the simulators (config_simulator.cpp) hold the cache models.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "nodetrace/cachesim/sweep.hpp"

namespace nodetrace::cachesim {

class ConfigSimulator {
 public:
  virtual ~ConfigSimulator() = default;
  // An animation frame begins; `split_level` is its K (split only).
  virtual void begin_frame(std::uint64_t animation_frame, std::uint32_t split_level) = 0;
  // `first_record`: 0-based number of records[0] in the trace (for errors).
  virtual void feed(const formats::Record* records, std::size_t count, std::uint64_t first_record,
                    const PreparedBatch& prepared) = 0;
  virtual ResultRow result() const = 0;
  virtual void append_level_rows(std::vector<LevelRow>& rows) const = 0;

};

// The simulator of one configuration with K `split_level` for the first
// animation frame (begin_frame gives each later frame's).
std::unique_ptr<ConfigSimulator> make_simulator(const NodeCacheConfig& config,
                                                std::uint32_t split_level,
                                                const TraceContext& context, bool per_level);

}  // namespace nodetrace::cachesim
