// Configurations answered together by a policy grid: the single caches of
// one block size under a policy set stacks cannot answer (plru of more than
// 2 ways, srrip, brrip, drrip) with 2 to 16 ways, demand fetch. Each keeps
// its own compact cache (packed_policy_cache.hpp); the grid turns each chunk
// of records once into the references its caches see, consecutive
// references to one block made one (they hit in every cache once the first
// is in: the repeat filter), and runs each cache over that list in turn, so
// its sets stay in the processor's cache for the whole chunk.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "sweep/config_simulator.hpp"

namespace nodetrace::cachesim {

// The key of the policy grid `config` can join, or empty when a grid does
// not answer it (another policy or scheme, more ways, prefetching,
// per-level counts).
std::string policy_grid_key(const Configuration& config, bool per_level);

// One simulator per member (configurations of one key, report order). The
// first one is the leader: only its feed() simulates (for all of them).
std::vector<std::unique_ptr<ConfigSimulator>> make_policy_grid(const std::vector<Configuration>& members,
                                                               const TraceContext& context);

}  // namespace nodetrace::cachesim
