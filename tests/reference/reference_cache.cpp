// The reference simulator (reference_cache.hpp). Written for reading, not
// speed: every fetch searches its set way by way.
#include "reference_cache.hpp"

#include <stdlib.h>

#include <algorithm>
#include <set>
#include <stdexcept>
#include <unordered_map>

namespace nodetrace::reference {

namespace {

constexpr std::uint64_t kNever = ~std::uint64_t{0};

}  // namespace

std::optional<Policy> policy_named(std::string_view name) {
  const std::pair<std::string_view, Policy> names[] = {
      {"lru", Policy::Lru},     {"fifo", Policy::Fifo},   {"random", Policy::Random}, {"plru", Policy::Plru},
      {"srrip", Policy::Srrip}, {"brrip", Policy::Brrip}, {"drrip", Policy::Drrip},   {"opt", Policy::Opt}};
  for (const auto& [text, policy] : names) {
    if (text == name) return policy;
  }
  return std::nullopt;
}

std::optional<Fetch> fetch_named(std::string_view name) {
  const std::pair<std::string_view, Fetch> names[] = {
      {"demand", Fetch::Demand}, {"always", Fetch::Always},           {"miss", Fetch::Miss},
      {"tagged", Fetch::Tagged}, {"load-forward", Fetch::LoadForward}, {"subblock", Fetch::Subblock}};
  for (const auto& [text, fetch] : names) {
    if (text == name) return fetch;
  }
  return std::nullopt;
}

// glibc's own generator (random_r), one per cache, seeded as srandom(1)
// seeds random(): the draws Dinero IV makes.
struct ReferenceCache::Generator {
  random_data data{};
  char state[128]{};
  Generator() { initstate_r(1, state, sizeof state, &data); }
  std::uint64_t next() {
    std::int32_t value = 0;
    random_r(&data, &value);
    return static_cast<std::uint64_t>(value);
  }
};

ReferenceCache::ReferenceCache(std::uint64_t sets, std::uint32_t ways, Policy policy)
    : sets_(sets),
      ways_(ways),
      policy_(policy),
      way_(sets, std::vector<Way>(ways)),
      tree_(policy == Policy::Plru ? sets : 0, std::vector<int>(ways, 0)),
      random_(std::make_unique<Generator>()) {
  if (sets == 0 || ways == 0) throw std::invalid_argument("reference cache without sets or ways");
}

ReferenceCache::~ReferenceCache() = default;
ReferenceCache::ReferenceCache(ReferenceCache&&) noexcept = default;
ReferenceCache& ReferenceCache::operator=(ReferenceCache&&) noexcept = default;

void ReferenceCache::set_future(std::vector<Event> events) {
  future_ = std::move(events);
  next_.assign(future_.size(), kNever);
  std::unordered_map<std::uint64_t, std::uint64_t> later;  // block -> its next event
  for (std::size_t i = future_.size(); i-- > 0;) {
    const auto found = later.find(future_[i].block);
    if (found != later.end()) next_[i] = found->second;
    later[future_[i].block] = i;
  }
  now_ = 0;
}

// When the block of event `event` is next fetched: an invalidation first
// means never (it is then gone, and the invalidation is not a use).
std::uint64_t ReferenceCache::next_use_after(std::size_t event) const {
  const std::uint64_t next = next_.at(event);
  if (next == kNever || future_[next].invalidate) return kNever;
  return next;
}

bool ReferenceCache::is_rrip() const {
  return policy_ == Policy::Srrip || policy_ == Policy::Brrip || policy_ == Policy::Drrip;
}

bool ReferenceCache::holds(std::uint64_t block) const {
  for (const Way& way : way_[block % sets_]) {
    if (way.valid && way.block == block) return true;
  }
  return false;
}

bool ReferenceCache::referenced(std::uint64_t block) const {
  for (const Way& way : way_[block % sets_]) {
    if (way.valid && way.block == block) return way.referenced;
  }
  return false;
}

bool ReferenceCache::access(std::uint64_t block, bool demand) {
  const bool opt = policy_ == Policy::Opt;
  if (opt && (now_ >= future_.size() || future_[now_].block != block || future_[now_].invalidate)) {
    throw std::logic_error("reference OPT cache: a fetch that is not the next event of its future");
  }
  const std::uint64_t next_use = opt ? next_use_after(now_) : 0;
  if (opt) ++now_;
  const std::uint64_t set = block % sets_;
  std::vector<Way>& ways = way_[set];
  ++clock_;
  for (std::uint32_t w = 0; w < ways_; ++w) {
    Way& way = ways[w];
    if (!way.valid || way.block != block) continue;
    if (policy_ == Policy::Lru) way.stamp = clock_;
    if (policy_ == Policy::Plru) touch_tree(set, w);
    if (is_rrip()) way.rrpv = 0;
    way.next_use = next_use;
    if (demand) way.referenced = true;
    return false;
  }
  std::uint32_t chosen = ways_;
  for (std::uint32_t w = 0; w < ways_; ++w) {
    if (!ways[w].valid) {
      chosen = w;
      break;
    }
  }
  if (chosen == ways_) {
    if (opt) {
      // Of the resident blocks and the incoming one, the farthest next use is kept out.
      std::uint64_t farthest = next_use;
      for (std::uint32_t w = 0; w < ways_; ++w) {
        if (ways[w].next_use > farthest) {
          farthest = ways[w].next_use;
          chosen = w;
        }
      }
      if (chosen == ways_) return true;  // the incoming block is farthest: bypassed
    } else {
      chosen = victim(set);
    }
  }
  Way& way = ways[chosen];
  way.valid = true;
  way.block = block;
  way.stamp = clock_;
  way.referenced = demand;
  way.next_use = next_use;
  if (policy_ == Policy::Plru) touch_tree(set, chosen);
  if (is_rrip()) {
    way.rrpv = insertion(set);
  }
  return true;
}

// The way a miss in a full set evicts, for every policy but OPT.
std::uint32_t ReferenceCache::victim(std::uint64_t set) {
  std::vector<Way>& ways = way_[set];
  switch (policy_) {
    case Policy::Lru:
    case Policy::Fifo: {  // least recently used / first filled
      std::uint32_t oldest = 0;
      for (std::uint32_t w = 1; w < ways_; ++w) {
        if (ways[w].stamp < ways[oldest].stamp) oldest = w;
      }
      return oldest;
    }
    case Policy::Random: {  // the k-th most recently filled, k = random() % ways
      std::vector<std::uint32_t> by_fill(ways_);
      for (std::uint32_t w = 0; w < ways_; ++w) by_fill[w] = w;
      std::sort(by_fill.begin(), by_fill.end(),
                [&](std::uint32_t a, std::uint32_t b) { return ways[a].stamp > ways[b].stamp; });
      return by_fill[random_->next() % ways_];
    }
    case Policy::Plru: {  // follow the bits from the root
      std::uint32_t node = 1;
      while (node < ways_) node = 2 * node + static_cast<std::uint32_t>(tree_[set][node]);
      return node - ways_;
    }
    case Policy::Srrip:
    case Policy::Brrip:
    case Policy::Drrip:
      for (;;) {  // the lowest way at 3, after ageing the set until one is
        for (std::uint32_t w = 0; w < ways_; ++w) {
          if (ways[w].rrpv == 3) return w;
        }
        for (Way& way : ways) ++way.rrpv;
      }
    case Policy::Opt:
      break;
  }
  throw std::logic_error("reference cache: no victim rule");
}

void ReferenceCache::invalidate(std::uint64_t block) {
  if (policy_ == Policy::Opt) {
    if (now_ >= future_.size() || future_[now_].block != block || !future_[now_].invalidate) {
      throw std::logic_error("reference OPT cache: an invalidation that is not the next event of its future");
    }
    ++now_;
  }
  for (Way& way : way_[block % sets_]) {
    if (way.valid && way.block == block) way.valid = false;
  }
}

// Every bit on the way's path points at the other half.
void ReferenceCache::touch_tree(std::uint64_t set, std::uint32_t way) {
  std::uint32_t node = way + ways_;
  while (node > 1) {
    const std::uint32_t parent = node / 2;
    tree_[set][parent] = node % 2 == 0 ? 1 : 0;
    node = parent;
  }
}

int ReferenceCache::bimodal() {
  ++bimodal_count_;
  return bimodal_count_ % 32 == 0 ? 2 : 3;
}

int ReferenceCache::insertion(std::uint64_t set) {
  if (policy_ == Policy::Srrip) return 2;
  if (policy_ == Policy::Brrip) return bimodal();
  const std::uint64_t leaders = std::min<std::uint64_t>(32, sets_ / 2);
  if (leaders > 0) {
    const std::uint64_t run = sets_ / leaders;
    if (set % run == 0) {  // an srrip leader
      selector_ = std::min(selector_ + 1, 1023);
      return 2;
    }
    if (set % run == run - 1) {  // a brrip leader
      selector_ = std::max(selector_ - 1, 0);
      return bimodal();
    }
  }
  return selector_ >= 512 ? bimodal() : 2;
}

std::uint32_t auto_split_level(const TraceFacts& trace, std::uint32_t frame, std::uint64_t high_size,
                               std::uint64_t block) {
  const std::vector<std::uint64_t>& levels = trace.nodes_per_level.at(frame);
  const std::uint64_t capacity = high_size / block;
  std::uint64_t nodes = 0;
  std::uint32_t k = 0;
  for (const std::uint64_t count : levels) {
    nodes += count;
    std::uint64_t blocks = 0;
    if (trace.contiguous_levels) {  // one after another from address 0
      const std::uint64_t bytes = nodes * trace.node_size;
      blocks = bytes == 0 ? 0 : (bytes - 1) / block + 1;
    } else {  // each node in blocks of its own
      blocks = nodes * std::max<std::uint64_t>(1, trace.node_size / block);
    }
    if (blocks > capacity) break;
    ++k;
  }
  return k;
}

namespace {

// The blocks a reference touches, as Dinero IV splits it: from its address
// to the end of its block, then block after block, wrapping at 2^64.
struct Part {
  std::uint64_t address;  // of the part: the reference's, then each block's start
  std::uint64_t block;    // block number
};

std::vector<Part> parts_of(std::uint64_t address, std::uint64_t size, std::uint64_t block) {
  std::vector<Part> parts;
  std::uint64_t left = size == 0 ? 1 : size;
  std::uint64_t at = address;
  while (left > 0) {
    parts.push_back({at, at / block});
    const std::uint64_t in_block = block - at % block;
    if (in_block >= left) break;
    left -= in_block;
    at = at - at % block + block;  // wraps at 2^64
  }
  return parts;
}

enum Role { kSingle = 0, kHigh = 1, kLow = 2 };

// The caches of one unit: single or low in `main`, high in `high` (cache policy).
struct UnitCaches {
  std::optional<ReferenceCache> main, high;
  std::set<std::uint64_t> retained;  // this frame's high blocks (retain)
};

ReferenceCache make_cache(std::uint64_t size, std::uint64_t block, std::uint32_t assoc, Policy policy) {
  const std::uint64_t blocks = size / block;
  const std::uint32_t ways = assoc == 0 ? static_cast<std::uint32_t>(blocks) : assoc;
  return ReferenceCache(blocks / ways, ways, policy);
}

void add(Counts& to, const Counts& from) {
  to.refs += from.refs;
  to.fetches += from.fetches;
  to.misses += from.misses;
  to.high_refs += from.high_refs;
  to.high_misses += from.high_misses;
  to.high_loads += from.high_loads;
  to.low_refs += from.low_refs;
  to.low_misses += from.low_misses;
  to.l2_refs += from.l2_refs;
  to.l2_fetches += from.l2_fetches;
  to.l2_misses += from.l2_misses;
  to.prefetches += from.prefetches;
  to.useful_prefetches += from.useful_prefetches;
}

// The treelet prefetcher's bytes for a miss on the block at `start`: from
// there to the end of its treelet (the one holding `start`, else the first
// beginning inside the block), at most `limit` bytes (0: no limit). Empty
// when no treelet is there.
std::optional<std::pair<std::uint64_t, std::uint64_t>> prefetch_bytes(const std::vector<Treelet>& treelets,
                                                                      std::uint64_t start, std::uint64_t block,
                                                                      std::uint64_t limit) {
  const Treelet* found = nullptr;
  for (const Treelet& treelet : treelets) {
    if (treelet.first <= start && start < treelet.first + treelet.bytes) found = &treelet;
  }
  for (const Treelet& treelet : treelets) {
    if (found == nullptr && start < treelet.first && treelet.first < start + block) found = &treelet;
  }
  if (found == nullptr) return std::nullopt;
  std::uint64_t end = found->first + found->bytes;
  if (limit != 0 && end > start + limit) end = start + limit;
  return std::make_pair(start, end);
}

}  // namespace

Result simulate(const TraceFacts& trace, const Config& config) {
  const unsigned units = config.private_units ? std::max(1u, trace.units) : 1;
  std::vector<std::uint32_t> k(trace.frames, 0);
  if (config.split) {
    for (std::uint32_t f = 0; f < trace.frames; ++f) {
      k[f] = config.split_level ? *config.split_level : auto_split_level(trace, f, config.high_size, config.block);
    }
  }
  auto role_of = [&](const TraceRecord& record) {
    if (!config.split) return kSingle;
    if (!record.level) throw std::invalid_argument("reference: an untagged record in the split scheme");
    return *record.level < k[record.frame] ? kHigh : kLow;
  };
  auto unit_of = [&](const TraceRecord& record) { return config.private_units ? record.unit : 0u; };

  std::vector<UnitCaches> caches(units);
  for (UnitCaches& unit : caches) {
    if (config.split) {
      unit.main = make_cache(config.low_size, config.block, config.assoc, config.policy);
      if (!config.retain) unit.high = make_cache(config.high_size, config.block, config.high_assoc, config.policy);
    } else {
      unit.main = make_cache(config.size, config.block, config.assoc, config.policy);
    }
  }
  if (config.policy == Policy::Opt) {  // each cache's whole stream, for the lookahead
    std::vector<std::vector<Event>> main_events(units), high_events(units);
    for (const TraceRecord& record : trace.records) {
      if (record.other_stream) continue;
      const Role role = role_of(record);
      if (record.type == 4 || (role == kHigh && config.retain)) continue;
      auto& events = (role == kHigh ? high_events : main_events)[unit_of(record)];
      if (record.type == 5) {
        events.push_back({record.address / config.block, true});
        continue;
      }
      for (const Part& part : parts_of(record.address, record.size, config.block)) {
        events.push_back({part.block, false});
      }
    }
    for (unsigned u = 0; u < units; ++u) {
      caches[u].main->set_future(std::move(main_events[u]));
      if (caches[u].high) caches[u].high->set_future(std::move(high_events[u]));
    }
  }
  std::optional<ReferenceCache> l2;
  if (config.l2) l2 = make_cache(config.l2->size, config.l2->block, config.l2->assoc, config.l2->policy);

  Result result;
  result.frames.assign(trace.frames, Counts{});
  for (std::uint32_t f = 0; f < trace.frames; ++f) result.frames[f].split_level = k[f];
  std::uint32_t frame = 0;
  for (const TraceRecord& record : trace.records) {
    if (record.frame != frame) {
      frame = record.frame;
      for (UnitCaches& unit : caches) unit.retained.clear();  // loaded once per frame
    }
    if (record.other_stream) continue;
    Counts counted;
    UnitCaches& unit = caches[unit_of(record)];
    const Role role = role_of(record);
    LevelCounts* level = record.level ? &result.levels[*record.level] : nullptr;
    counted.refs = 1;
    if (level) ++level->refs;
    (role == kHigh ? counted.high_refs : counted.low_refs) += role == kSingle ? 0 : 1;
    auto miss = [&](std::uint64_t block) {
      ++counted.misses;
      if (role == kHigh) ++counted.high_misses;
      if (role == kLow) ++counted.low_misses;
      if (level) ++level->misses;
      (void)block;
    };
    auto to_l2 = [&](std::uint64_t block) {
      if (!l2) return;
      ++counted.l2_refs;
      for (const Part& part : parts_of(block * config.block, config.block, config.l2->block)) {
        ++counted.l2_fetches;
        counted.l2_misses += l2->access(part.block) ? 1 : 0;
      }
    };
    ReferenceCache* cache = role == kHigh ? (config.retain ? nullptr : &*unit.high) : &*unit.main;
    if (record.type == 5) {
      if (cache) cache->invalidate(record.address / config.block);
    } else if (record.type != 4) {
      for (const Part& part : parts_of(record.address, record.size, config.block)) {
        ++counted.fetches;
        if (!cache) {  // retained: loaded at its first use in the frame, never a miss
          if (unit.retained.insert(part.block).second) {
            ++counted.high_loads;
            if (config.count_loads) miss(part.block);
            to_l2(part.block);
            if (unit.retained.size() > config.high_size / config.block) result.high_levels_do_not_fit = true;
          }
          continue;
        }
        const bool referenced_before = cache->referenced(part.block);
        // A block placed by a treelet prefetch is unreferenced until a demand fetch uses it.
        if (config.prefetch && cache->holds(part.block) && !referenced_before) ++counted.useful_prefetches;
        const bool missed = cache->access(part.block);
        if (missed) {
          miss(part.block);
          to_l2(part.block);
        }
        const bool prefetching_cache = role != kHigh || !config.prefetch_low;
        if (config.prefetch && missed && prefetching_cache && record.frame < trace.treelets.size() &&
            trace.treelets[record.frame]) {
          const auto range = prefetch_bytes(*trace.treelets[record.frame], part.block * config.block, config.block,
                                            config.prefetch_bytes);
          for (std::uint64_t b = part.block + 1; range && b * config.block < range->second; ++b) {
            if (cache->holds(b)) continue;
            cache->access(b, false);
            ++counted.prefetches;
          }
        }
        // Dinero IV prefetches on demand reads and instruction fetches only,
        // after the demand fetch is in place, from the part's address.
        if (config.fetch == Fetch::Demand || (record.type != 0 && record.type != 2)) continue;
        const std::uint64_t b = config.block;
        const std::uint64_t ahead = part.address + std::uint64_t{config.prefetch_distance} * b;
        std::optional<std::uint64_t> target = ahead - ahead % b;
        switch (config.fetch) {
          case Fetch::Miss:
            if (!missed) target.reset();
            break;
          case Fetch::Tagged:
            if (!missed && referenced_before) target.reset();
            break;
          case Fetch::LoadForward:
            if (ahead / b != part.address / b) target.reset();
            break;
          case Fetch::Subblock:
            if (*target / b != part.address / b) *target -= b;
            break;
          default:
            break;
        }
        if (target) cache->access(*target / b, false);
      }
    }
    add(result.total, counted);
    add(result.frames.at(record.frame), counted);
  }
  result.total.split_level = k.empty() ? 0 : k[0];
  return result;
}

}  // namespace nodetrace::reference
