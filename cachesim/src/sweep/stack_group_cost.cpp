// What a stack group costs (StackGroupCost, stack_group.hpp): the work a
// probe's walk found at each set count, and the cut of a group into pieces
// for threads where the costliest piece is cheapest.
#include <algorithm>
#include <cmath>
#include <optional>

#include "nodetrace/cachesim/models/set_stacks.hpp"
#include "sweep/stack_group.hpp"

namespace nodetrace::cachesim {

using formats::AccessType;

namespace {

// The cost units (work per record; one set count looked at is about 1):
// rough weights of this machine's loops, enough to balance threads.
constexpr double kRouterCost = 1.0;         // reading a record, its block, its side
constexpr double kPlaceCost = 0.5;          // one place searched and moved down a stack
constexpr double kDirectMappedCost = 0.5;   // one set count of the branchless pass
constexpr double kRetainCost = 2.0;         // one high fetch of a retained high cache

// One side's set counts (fewest sets first): the work found at each, and
// the share of records that reached it.
struct SideWork {
  std::vector<unsigned> log2_sets;
  std::vector<double> work;
  std::vector<double> visits;
  bool direct_mapped = true;

  SideWork(const SetStacks& stacks, std::vector<unsigned> sets, double records) {
    std::sort(sets.begin(), sets.end());
    sets.erase(std::unique(sets.begin(), sets.end()), sets.end());
    log2_sets = std::move(sets);
    direct_mapped = stacks.direct_mapped();
    for (const unsigned log2 : log2_sets) {
      const SetStacks::Walk walk = stacks.walk(log2);
      // Without a probe every fetch is taken to reach every set count. The
      // first batch (the probe) tends to be more coherent than the trace
      // (a scanline render's first rows): the share reaching a set count is
      // flattened (its square root), the places per visit kept.
      const double probed = records > 0 ? static_cast<double>(walk.visits) / records : 1.0;
      const double reached = std::sqrt(probed);
      const double places = walk.visits > 0 ? static_cast<double>(walk.places) /
                                                  static_cast<double>(walk.visits) * reached
                                            : 0.0;
      visits.push_back(reached);
      work.push_back(reached + kPlaceCost * places);
    }
  }

  // The set counts `wanted` (sorted) walked by one stack of their own,
  // records sent to this side a share `share` of all; the first of them
  // is looked at by every fetch (the walk of fewer sets before it, which
  // would have stopped some fetches, is another piece's), or, `entered`,
  // only the fetches that reach it, after a direct-mapped look of all.
  double cost(const std::vector<unsigned>& wanted, double share, bool branchless, bool entered) const {
    if (wanted.empty()) return 0;
    if (branchless && direct_mapped) return kDirectMappedCost * static_cast<double>(wanted.size()) * share;
    double cost = 0;
    for (std::size_t l = 0; l < log2_sets.size(); ++l) {
      if (std::binary_search(wanted.begin(), wanted.end(), log2_sets[l])) cost += work[l];
    }
    const std::size_t first = static_cast<std::size_t>(
        std::lower_bound(log2_sets.begin(), log2_sets.end(), wanted.front()) - log2_sets.begin());
    if (entered) return cost + (first > 0 ? kDirectMappedCost * share : 0.0);
    return cost + std::max(0.0, share - visits[first]);
  }
};

}  // namespace

struct StackGroupCost::Profile {
  bool split = false;
  bool retain = false;
  bool per_level = false;
  double high_share = 0;
  std::vector<unsigned> member_low;
  std::vector<unsigned> member_high;
  std::optional<SideWork> low;
  std::optional<SideWork> high;
};

StackGroupCost::StackGroupCost(const std::vector<Configuration>& members,
                               std::uint32_t split_level, const TraceContext& context,
                               bool per_level, const formats::Record* sample, std::size_t count) {
  std::uint64_t probed = 0;
  for (std::size_t i = 0; i < count; ++i) {
    probed += sample[i].type <= AccessType::Misc && formats::is_level(sample[i].tag);
  }
  auto made = std::make_shared<Profile>();
  Profile& profile = *made;
  probe_stack_group(members, split_level, context, sample, count, [&](const StackGroupProbe& probe) {
    profile.split = probe.split;
    profile.retain = probe.retain;
    profile.per_level = per_level;
    const double records = static_cast<double>(probed);
    profile.high_share = probed > 0 ? static_cast<double>(probe.high_refs) / records
                                    : (profile.split ? 0.5 : 0.0);
    profile.member_low = probe.member_low;
    profile.member_high = probe.member_high;
    profile.low.emplace(*probe.low, profile.member_low, records);
    if (probe.high) profile.high.emplace(*probe.high, profile.member_high, records);
  });
  profile_ = std::move(made);
}

std::size_t StackGroupCost::max_pieces() const { return profile_->low->log2_sets.size(); }

double StackGroupCost::piece_cost(unsigned first_low, unsigned last_low,
                                  std::vector<std::size_t>* members) const {
  const Profile& profile = *profile_;
  std::vector<unsigned> low_sets;
  std::vector<unsigned> high_sets;
  for (std::size_t m = 0; m < profile.member_low.size(); ++m) {
    const unsigned low = profile.member_low[m];
    if (low < first_low || low > last_low) continue;
    if (members) members->push_back(m);
    low_sets.push_back(low);
    if (profile.high) high_sets.push_back(profile.member_high[m]);
  }
  std::sort(low_sets.begin(), low_sets.end());
  low_sets.erase(std::unique(low_sets.begin(), low_sets.end()), low_sets.end());
  std::sort(high_sets.begin(), high_sets.end());
  high_sets.erase(std::unique(high_sets.begin(), high_sets.end()), high_sets.end());
  const double low_share = 1.0 - profile.high_share;
  double cost = kRouterCost + profile.low->cost(low_sets, low_share, !profile.per_level, true);
  if (profile.retain) {
    cost += kRetainCost * profile.high_share;
  } else if (profile.high) {
    cost += profile.high->cost(high_sets, profile.high_share, false, false);
  }
  return cost;
}

std::vector<StackPiece> StackGroupCost::cut(std::size_t pieces) const {
  const std::vector<unsigned>& sets = profile_->low->log2_sets;
  const std::size_t levels = sets.size();
  pieces = std::clamp<std::size_t>(pieces, 1, levels);
  // best[p][j]: the least cost of the costliest piece when the first j
  // set counts make p pieces; from[p][j] where the last of them begins.
  constexpr double kNone = 1e300;
  std::vector<std::vector<double>> best(pieces + 1, std::vector<double>(levels + 1, kNone));
  std::vector<std::vector<std::size_t>> from(pieces + 1, std::vector<std::size_t>(levels + 1, 0));
  best[0][0] = 0;
  for (std::size_t p = 1; p <= pieces; ++p) {
    for (std::size_t j = p; j <= levels; ++j) {
      for (std::size_t i = p - 1; i < j; ++i) {
        if (best[p - 1][i] >= kNone) continue;
        const double worst = std::max(best[p - 1][i], piece_cost(sets[i], sets[j - 1], nullptr));
        if (worst < best[p][j]) {
          best[p][j] = worst;
          from[p][j] = i;
        }
      }
    }
  }
  std::vector<StackPiece> cut(pieces);
  std::size_t end = levels;
  for (std::size_t p = pieces; p > 0; --p) {
    const std::size_t begin = from[p][end];
    StackPiece& piece = cut[p - 1];
    piece.cost = piece_cost(sets[begin], sets[end - 1], &piece.members);
    if (begin > 0) piece.entry_log2_sets = sets[begin - 1];
    end = begin;
  }
  return cut;
}

}  // namespace nodetrace::cachesim
