// Configurations answered together by set stacks (set_stacks.hpp): every
// LRU (or direct-mapped) cache of one block size behind the same router
// (single, or split with the same K in every animation frame) is one
// question, so one pass answers all of them. The split scheme's high caches
// are a second set of stacks under `cache` and one retain set under
// `retain` (the blocks a frame touches do not depend on the high cache's
// size; each member checks its own capacity).
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "nodetrace/cachesim/models/set_stacks.hpp"
#include "sweep/config_simulator.hpp"
#include "sweep/grid_filter_output.hpp"

namespace nodetrace::cachesim {

// The key of the stack group `config` can join, or empty when set stacks do
// not answer it (FIFO or random with ways, more ways than stacks keep).
std::string stack_group_key(const Configuration& config);

// The member whose high cache holds the fewest blocks (the first of them).
std::size_t tightest_member(const std::vector<Configuration>& members);

// What a stack group of `members` (built as make_stack_group builds it,
// no per-level counts) found walking sample records: its routing, the set
// counts of each member, and its stacks, whose walk statistics tell how far
// fetches went (valid only during `look`).
struct StackGroupProbe {
  bool split = false;
  bool retain = false;
  std::uint64_t high_refs = 0;
  std::vector<unsigned> member_low, member_high;  // log2 of each member's low and high set counts
  const SetStacks* low = nullptr;
  const SetStacks* high = nullptr;  // null: no high stacks
};
void probe_stack_group(const std::vector<Configuration>& members, std::uint32_t split_level,
                       const TraceContext& context, const formats::Record* sample, std::size_t count,
                       const std::function<void(const StackGroupProbe&)>& look);

// One simulator per member (configurations of one key, report order). The
// first one is the leader: only its feed() simulates (for all of them);
// the others' feed() must not be called. All members must be fed by the
// same thread and see the same begin_animation_frame calls. `retain_bound` (split
// under `retain`, when the group is a piece of a larger one): the larger
// group's tightest member, whose capacity and name the retain set uses;
// null: the tightest of `members`. `entry_log2_sets` (a piece past the
// first): the set count of the group's low caches just below this piece's,
// kept one block deep in front of its stacks, so that only the fetches the
// whole group's walk brings here reach them (see StackPiece).
// `grid_filtered` (single caches): the output of the policy grid of the
// same block size, whose leader is fed each chunk just before this group's
// on the same thread; where it has lists of the chunk, the stacks walk
// them.
std::vector<std::unique_ptr<ConfigSimulator>> make_stack_group(
    const std::vector<Configuration>& members, std::uint32_t split_level,
    const TraceContext& context, bool per_level, const Configuration* retain_bound = nullptr,
    std::optional<unsigned> entry_log2_sets = std::nullopt,
    std::shared_ptr<const GridFilterOutput> grid_filtered = nullptr);

// Some of a stack group's members (indices into them, in order) and their
// estimated work per record (units: a set count looked at by a fetch is
// about 1; comparable with the sweep's estimates of other simulators). A
// piece past the first has an entry: the group's low set count just below
// its own. A fetch goes on past it exactly when its block is not the last
// one fetched in its set there (on top of a set, a block is on top in every
// larger set count), which one block per set tells: a direct-mapped look
// instead of the walk of the set counts before it.
struct StackPiece {
  std::vector<std::size_t> members;
  double cost = 0;
  std::optional<unsigned> entry_log2_sets;
};

// What a stack group costs, from a probe: its stacks walk sample records
// (the first batch's), which shows how far the walk goes in each set
// count. A group may be cut into pieces for threads, each a contiguous
// range of the low (single) caches' set counts and a stack group of its
// own: each set count's stacks see the same fetches whatever the others
// do (the walk only stops early), so the pieces' counts are the group's;
// the hand-over at an invalidate is per member, so it too. A piece past
// the first costs a direct-mapped look (its entry) for every fetch.
class StackGroupCost {
 public:
  StackGroupCost(const std::vector<Configuration>& members, std::uint32_t split_level,
                 const TraceContext& context, bool per_level, const formats::Record* sample,
                 std::size_t count);

  // The most pieces cut() makes: the number of low set counts.
  std::size_t max_pieces() const;
  // At most `pieces` pieces (fewest sets first), cut where the costliest
  // piece is cheapest.
  std::vector<StackPiece> cut(std::size_t pieces) const;

 private:
  struct Profile;
  double piece_cost(unsigned first_low, unsigned last_low, std::vector<std::size_t>* members) const;
  std::shared_ptr<const Profile> profile_;
};

}  // namespace nodetrace::cachesim
