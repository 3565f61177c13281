// Configurations answered together by a policy grid: the single caches of
// one block size under a policy set stacks cannot answer (plru of more than
// 2 ways, srrip, brrip, drrip) with 2 to 16 ways, demand fetch. Each keeps
// its own compact cache (packed_policy_cache.hpp). The grid reads each
// chunk of records once (when each is one demand fetch, the first filter
// reads the records themselves); then, for each set count of its
// members, fewest sets first, a filter leaves out every fetch of the block
// its set fetched last (a hit in every cache of that set count, whose
// update changes nothing: see SetFilter), and that set count's members run
// together over what is left (packed_cache_bundle.hpp), their sets staying
// in the processor's cache for the whole chunk. On a rendered kd-tree trace
// with 8-byte blocks no fetch repeats the one before it, but a set of 64
// sets leaves out 40 % of them and one of 512 sets 80 %.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "sweep/config_simulator.hpp"
#include "sweep/grid_filter_output.hpp"

namespace nodetrace::cachesim {

// The key of the policy grid `config` can join, or empty when a grid does
// not answer it (another policy or scheme, more ways, prefetching,
// per-level counts).
std::string policy_grid_key(const Configuration& config, bool per_level);

struct PolicyGridSimulators {
  // One per member (configurations of one key, report order). The first
  // one is the leader: only its feed() simulates (for all of them).
  std::vector<std::unique_ptr<ConfigSimulator>> members;
  std::shared_ptr<const GridFilterOutput> filtered;
};
PolicyGridSimulators make_policy_grid(const std::vector<Configuration>& members, const TraceContext& context);

}  // namespace nodetrace::cachesim
