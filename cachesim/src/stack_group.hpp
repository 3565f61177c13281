// Configurations answered together by set stacks (set_stacks.hpp): every
// LRU (or direct-mapped) cache of one block size behind the same router
// (single, or split with the same K in every animation frame) is one
// question, so one pass answers all of them. The split scheme's high caches
// are a second set of stacks under `cache` and one retain set under
// `retain` (the blocks a frame touches do not depend on the high cache's
// size; each member checks its own capacity).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "config_simulator.hpp"

namespace nodetrace::cachesim {

// The key of the stack group `config` can join, or empty when set stacks do
// not answer it (FIFO or random with ways, more ways than stacks keep).
std::string stack_group_key(const NodeCacheConfig& config);

// One simulator per member (configurations of one key, report order). The
// first one is the leader: only its feed() simulates (for all of them);
// the others' feed() must not be called. All members must be fed by the
// same thread and see the same begin_frame calls.
std::vector<std::unique_ptr<ConfigSimulator>> make_stack_group(
    const std::vector<NodeCacheConfig>& members, std::uint32_t split_level,
    const TraceContext& context, bool per_level);

}  // namespace nodetrace::cachesim
