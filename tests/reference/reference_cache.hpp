// The reference cache simulator: the plainest simulator we could write that
// is obviously right, against which every path of `cachesim run` is held
// (tests/differential/config_case_*.cpp, test_replacement_policies.cpp). It
// shares no code with cachesim: each set is an array of ways searched one by
// one, each policy is the README's "Replacement policies" rule written out,
// OPT looks ahead over the whole stream its cache will see, the split scheme
// follows DESIGN.md "Cache model", and the fetch policies and the counting
// of references that span blocks follow Dinero IV d4-7 (ref.c), with 64-bit
// addresses that wrap at 2^64 as Dinero IV's wrap at 2^32.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace nodetrace::reference {

enum class Policy { Lru, Fifo, Random, Plru, Srrip, Brrip, Drrip, Opt };
enum class Fetch { Demand, Always, Miss, Tagged, LoadForward, Subblock };

// cachesim run's names: lru ... opt; demand, always, miss, tagged, load-forward, subblock.
std::optional<Policy> policy_named(std::string_view name);
std::optional<Fetch> fetch_named(std::string_view name);

// One event of the stream a cache sees: a fetch of a block, or an
// invalidation of one. OPT looks ahead over these.
struct Event {
  std::uint64_t block = 0;
  bool invalidate = false;
};

class ReferenceCache {
 public:
  ReferenceCache(std::uint64_t sets, std::uint32_t ways, Policy policy);
  ~ReferenceCache();
  ReferenceCache(ReferenceCache&&) noexcept;
  ReferenceCache& operator=(ReferenceCache&&) noexcept;

  // OPT only: every event this cache will see, in order. access() and
  // invalidate() must then be called for exactly these events.
  void set_future(std::vector<Event> events);

  // A fetch of `block`; true on a miss. `demand`: false for a prefetch,
  // which does not set the block's referenced bit (tagged prefetch).
  bool access(std::uint64_t block, bool demand = true);
  void invalidate(std::uint64_t block);
  bool holds(std::uint64_t block) const;
  // Whether a demand fetch has used `block` since it was placed.
  bool referenced(std::uint64_t block) const;

 private:
  struct Way {
    bool valid = false;
    std::uint64_t block = 0;
    std::uint64_t stamp = 0;  // LRU: last use; FIFO and random: fill
    int rrpv = 3;
    bool referenced = false;
    std::uint64_t next_use = 0;  // OPT: index of the next fetch, or "never"
  };
  struct Generator;  // glibc's random(), seeded by srandom(1): Dinero IV's

  bool is_rrip() const;
  void touch_tree(std::uint64_t set, std::uint32_t way);
  int bimodal();
  int insertion(std::uint64_t set);
  std::uint64_t next_use_after(std::size_t event) const;
  std::uint32_t victim(std::uint64_t set);

  std::uint64_t sets_;
  std::uint32_t ways_;
  Policy policy_;
  std::vector<std::vector<Way>> way_;
  std::vector<std::vector<int>> tree_;  // PLRU: node 1 the root; a bit 1 points right
  std::uint64_t clock_ = 0;
  std::uint64_t bimodal_count_ = 0;
  int selector_ = 511;
  std::unique_ptr<Generator> random_;
  std::vector<Event> future_;
  std::vector<std::uint64_t> next_;  // OPT: per event, the next event of its block (index), or never
  std::size_t now_ = 0;
};

// What the reference reads of a trace: the records as cachesim sees them
// (din records at the address rounded down to 4, size 4), each record's
// animation frame, each frame's nodes per level, the layout.
struct TraceRecord {
  std::uint64_t address = 0;
  std::uint32_t size = 4;
  int type = 0;  // 0 read, 1 write, 2 instruction fetch, 3 misc, 4 copy-back, 5 invalidate
  std::optional<std::uint32_t> level;  // nullopt: untagged
  char other_stream = 0;               // 'p' or 't': a record of another stream, counted apart, never simulated
  unsigned unit = 0;
  std::uint32_t frame = 0;  // index into TraceFacts::nodes_per_level
};

// One treelet of a frame's map: bytes [first, first + bytes).
struct Treelet {
  std::uint64_t first = 0, bytes = 0;
};

struct TraceFacts {
  std::vector<TraceRecord> records;
  // Per frame (index as TraceRecord::frame): its treelet map, nullopt when
  // the frame has none (empty: no frame has one).
  std::vector<std::optional<std::vector<Treelet>>> treelets;
  std::vector<std::vector<std::uint64_t>> nodes_per_level;  // per frame (empty: no marker counts)
  std::uint32_t frames = 1;
  bool contiguous_levels = true;  // layout bfl (else nodes scattered, dfl)
  std::uint64_t node_size = 8;
  unsigned units = 1;
};

struct L2Config {
  std::uint64_t size = 0;
  std::uint64_t block = 64;
  std::uint32_t assoc = 8;  // 0: full
  Policy policy = Policy::Lru;
};

struct Config {
  bool split = false;
  std::uint64_t size = 8192;
  std::uint64_t block = 8;
  std::uint32_t assoc = 1;  // single / low cache; 0: full
  Policy policy = Policy::Lru;
  bool retain = true;
  std::uint64_t high_size = 0, low_size = 0;
  std::uint32_t high_assoc = 1;  // 0: full
  std::optional<std::uint32_t> split_level;  // nullopt: auto
  bool count_loads = false;
  Fetch fetch = Fetch::Demand;
  std::uint32_t prefetch_distance = 1;
  bool private_units = false;
  std::optional<L2Config> l2;
  // --prefetch treelet[:BYTES] (0: the whole treelet); `prefetch_low`:
  // treelet-low, into the split scheme's low cache only.
  bool prefetch = false, prefetch_low = false;
  std::uint64_t prefetch_bytes = 0;
};

struct Counts {
  std::uint64_t refs = 0, fetches = 0, misses = 0;
  std::uint64_t high_refs = 0, high_misses = 0, high_loads = 0, low_refs = 0, low_misses = 0;
  std::uint32_t split_level = 0;  // K (of the first frame for the totals)
  std::uint64_t l2_refs = 0, l2_fetches = 0, l2_misses = 0;
  std::uint64_t prefetches = 0, useful_prefetches = 0;
};

struct LevelCounts {
  std::uint64_t refs = 0, misses = 0;
};

struct Result {
  Counts total;
  std::vector<Counts> frames;                    // per animation frame
  std::map<std::uint32_t, LevelCounts> levels;  // per node level
  // A retained high cache that a frame's high levels do not fit (the run must fail).
  bool high_levels_do_not_fit = false;
};

// K = auto of a frame: the largest K whose levels' nodes occupy no more
// blocks than the high cache holds.
std::uint32_t auto_split_level(const TraceFacts& trace, std::uint32_t frame, std::uint64_t high_size,
                               std::uint64_t block);

Result simulate(const TraceFacts& trace, const Config& config);

}  // namespace nodetrace::reference
