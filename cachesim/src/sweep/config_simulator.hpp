// One configuration's simulator, as the sweep drives it: fed chunks of
// records in trace order, told where animation frames begin, asked for its
// counts. The sweep (sweep.cpp) partitions, routes batches and keeps the
// per-frame rows; the simulators (config_simulator.cpp) hold the cache models.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "nodetrace/cachesim/sweep/sweep.hpp"

namespace nodetrace::cachesim {

class ConfigSimulator {
 public:
  virtual ~ConfigSimulator() = default;
  // An animation frame begins; `split_level` is its K (split only).
  virtual void begin_animation_frame(std::uint64_t animation_frame, std::uint32_t split_level) = 0;
  // `first_record`: 0-based number of records[0] in the trace (for errors).
  virtual void feed(const formats::Record* records, std::size_t count, std::uint64_t first_record,
                    const PreparedBatch& prepared) = 0;
  virtual ResultRow result() const = 0;
  virtual void append_level_rows(std::vector<LevelRow>& rows) const = 0;
  // The treelet map of the animation frame that begins (nullptr: none);
  // only treelet prefetchers use it.
  virtual void begin_treelets(const formats::TreeletMap*) {}

};

// Split configurations whose caches are all direct mapped (the retain set
// or a direct-mapped high cache), of one block size, can be fed by one loop
// whatever their K: those of equal non-empty keys, at most kMaxTogether.
inline constexpr std::size_t kMaxTogether = 8;
std::string together_key(const Configuration& config, bool per_level);
// Their simulators (`split_levels`: each one's K of the first animation
// frame); the first one's feed() feeds all, the others' do nothing.
std::vector<std::unique_ptr<ConfigSimulator>> make_together(
    const std::vector<Configuration>& configs, const std::vector<std::uint32_t>& split_levels,
    const TraceContext& context);

// The streams of opt caches by the fetches they see, so that the opt
// configurations of one block size and router keep them once (8 bytes a
// fetch) whatever their sizes and ways.
class SharedOptStream;
using OptStreams = std::map<std::string, std::shared_ptr<SharedOptStream>>;

// The simulator of one configuration with K `split_level` for the first
// animation frame (begin_animation_frame gives each later frame's).
// `opt_streams`: the streams its opt caches share with the configurations
// made with the same map (null: their own); all of them must be fed the
// same records, and counted only after the last.
std::unique_ptr<ConfigSimulator> make_simulator(const Configuration& config,
                                                std::uint32_t split_level,
                                                const TraceContext& context, bool per_level,
                                                OptStreams* opt_streams = nullptr);

}  // namespace nodetrace::cachesim
