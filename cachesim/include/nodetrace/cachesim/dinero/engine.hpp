// The Dinero-IV-exact cache engine: a hierarchy of one to five levels of
// caches, with any of Dinero IV's fetch (prefetch) policies, that gives the
// numbers Dinero IV (d4-7) gives for the same references and configuration.
//
//   HierarchyConfig config;
//   config.levels.push_back({.data = CacheConfig{.size = 8192, .block_size = 8}});
//   Hierarchy h(config);                    // throws base::UsageError
//   for (const Record& r : records) h.access(formats::dinero_view(r, form));
//   h.finish();                             // Dinero's end-of-run copy-back
//   const Stats& s = h.stats(1, CacheKind::Data);
//
// Records are simulated exactly as given (address, size, type). Dinero IV
// rounds din addresses down to 4 bytes and gives din records size 4: pass
// formats::dinero_view(record, form), or use access_batch(records, form).
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "nodetrace/cachesim/models/cache_geometry.hpp"
#include "nodetrace/formats/record/record.hpp"

namespace nodetrace::cachesim {

inline constexpr int kMaxLevels = 5;  // Dinero IV's MAX_LEV

// Dinero's `T` in -lN-T...: unified, instruction or data cache.
enum class CacheKind : std::uint8_t { Unified = 0, Instruction = 1, Data = 2 };
// The letter T of a CacheKind (0, 1, 2) in Dinero IV's names: u, i, d.
constexpr char cache_kind_letter(int kind) { return "uid"[kind]; }

// -lN-Twalloc a|n|f: allocate on a write miss always, never, or only when the
// write covers whole sub-blocks (no fetch needed).
enum class WriteAllocate : std::uint8_t { Always, Never, NoFetch };
// -lN-Twback a|n|f: write back, write through, or write back only when no
// fetch is needed (affected sub-blocks valid or wholly written).
enum class WriteBack : std::uint8_t { Always, Never, NoFetch };

// -lN-Tfetch d|a|m|t|l|s: demand only; prefetch on every read / instruction
// fetch; only on a miss; on a miss or the first demand reference to a
// prefetched sub-block (tagged); always but never into the next block (load
// forward); always, wrapping round within the block (sub-block).
enum class FetchPolicy : std::uint8_t { Demand, Always, Miss, Tagged, LoadForward, SubBlock };

// Command-line names (demand, always, miss, tagged, load-forward, subblock)
// and Dinero IV's -lN-Tfetch letters (d, a, m, t, l, s).
std::string_view fetch_policy_name(FetchPolicy policy);
std::optional<FetchPolicy> parse_fetch_policy_name(std::string_view name);
char dinero_fetch_letter(FetchPolicy policy);

struct CacheConfig {
  std::uint64_t size = 0;            // bytes; power of two
  std::uint32_t block_size = 0;      // bytes; power of two
  std::uint32_t sub_block_size = 0;  // bytes; power of two dividing block_size; 0 = block_size
  std::uint32_t assoc = 1;           // ways; size / block_size = fully associative
  ReplacementPolicy replacement = ReplacementPolicy::Lru;
  WriteAllocate write_allocate = WriteAllocate::Always;  // ignored for instruction caches
  WriteBack write_back = WriteBack::Always;              // ignored for instruction caches
  bool classify_misses = false;  // -lN-Tccc: compulsory / capacity / conflict
  FetchPolicy fetch = FetchPolicy::Demand;
  // -lN-Tpfdist: how far ahead a prefetch goes, in sub-blocks (not Demand).
  std::uint32_t prefetch_distance = 1;
  // -lN-Tpfabort: the percentage (0-100) of prefetches thrown away at random.
  std::uint32_t prefetch_abort = 0;

  CacheGeometry geometry() const { return {size, block_size, assoc, replacement}; }
  std::uint32_t effective_sub_block_size() const {
    return sub_block_size == 0 ? block_size : sub_block_size;
  }
};

// One level: a unified cache, or an instruction and/or a data cache. A level
// with only a data cache sends instruction fetches on to the next level that
// has an instruction or unified cache (or memory), as Dinero IV does.
struct LevelConfig {
  std::optional<CacheConfig> unified;
  std::optional<CacheConfig> instruction;
  std::optional<CacheConfig> data;
};

class Hierarchy;

struct HierarchyConfig {
  std::vector<LevelConfig> levels;  // levels[0] is L1 (closest to the processor)
  // Dinero's -skipcount, -maxcount, -flushcount (0: off), applied by access().
  std::uint64_t skip_count = 0;
  std::uint64_t max_count = 0;
  std::uint64_t flush_count = 0;
  // Dinero's -on-trigger / -off-trigger (0: off): references are discarded
  // until one at on_trigger, and from one at off_trigger (the trigger
  // references themselves are discarded too). Applied after skip_count.
  std::uint64_t on_trigger = 0;
  std::uint64_t off_trigger = 0;
  // Dinero's -stat-interval: when set, on_stat_interval is called every
  // stat_interval simulated references (before a flush due at the same one).
  std::uint64_t stat_interval = 0;
  std::function<void(const Hierarchy&)> on_stat_interval;

  // Throws base::UsageError, naming the cache (e.g. "l1-dcache"), for
  // geometry that cannot exist or a hierarchy Dinero IV refuses.
  void validate() const;
};

// A one-level hierarchy with `cache` as L1 of `kind`.
HierarchyConfig single_level(const CacheConfig& cache, CacheKind kind = CacheKind::Unified);

// Counts of one kind of fetch (demand, or prefetch), as Dinero IV keeps them.
// Per-type arrays are indexed by access type: Read, Write, InstructionFetch,
// Misc (0..3); copy-back and invalidate records are not fetches and are never
// counted. Prefetches are only ever of the Read and InstructionFetch types.
struct FetchCounts {
  using PerType = std::array<std::uint64_t, 4>;
  PerType fetches{};       // fetches (a reference spanning k blocks counts k)
  PerType misses{};        // a needed sub-block was absent
  PerType block_misses{};  // the whole block was absent
  // With classify_misses only:
  PerType compulsory{};
  PerType capacity{};
  PerType conflict{};
  PerType compulsory_block{};
  PerType capacity_block{};
  PerType conflict_block{};

  FetchCounts& operator+=(const FetchCounts& other);
  friend bool operator==(const FetchCounts&, const FetchCounts&) = default;
};

// Statistics of one cache: the demand counts, the prefetch counts (zero
// under FetchPolicy::Demand) and the traffic.
struct Stats : FetchCounts {
  FetchCounts prefetch;
  std::uint64_t multi_block_refs = 0;   // references split at a block boundary
  std::uint64_t bytes_from_memory = 0;  // bytes read from the next level
  std::uint64_t bytes_to_memory = 0;    // bytes written to the next level

  static std::uint64_t total(const PerType& per_type) {
    return per_type[0] + per_type[1] + per_type[2] + per_type[3];
  }
  // Dinero's "Data" column: read + write + misc.
  static std::uint64_t data(const PerType& per_type) {
    return per_type[0] + per_type[1] + per_type[3];
  }
  std::uint64_t demand_fetches() const { return total(fetches); }
  std::uint64_t demand_misses() const { return total(misses); }

  Stats& operator+=(const Stats& other);
  friend bool operator==(const Stats&, const Stats&) = default;
};

class Hierarchy {
 public:
  // Validates `config` (base::UsageError) and builds empty caches.
  explicit Hierarchy(const HierarchyConfig& config);
  ~Hierarchy();
  Hierarchy(Hierarchy&&) noexcept;
  Hierarchy& operator=(Hierarchy&&) noexcept;

  // Feeds one reference, as Dinero IV's main loop does: the first skip_count
  // references are dropped; once max_count references have been simulated the
  // next one is refused (returns false, max_count_exceeded() becomes true,
  // Dinero prints "---Maximum address count exceeded."); every flush_count
  // simulated references all caches are copied back and invalidated.
  // Instruction fetches go to the instruction side, invalidates to both
  // sides, everything else to the data side. Returns true when accepted.
  bool access(const formats::Record& record);

  // access(formats::dinero_view(r, form)) for each record, stopping at the
  // first refused one. Returns the number of records consumed (accepted or
  // skipped). This is the fast path for long traces.
  std::size_t access_batch(std::span<const formats::Record> records, formats::RecordForm form);

  // Dinero's flush: copy back dirty blocks, then invalidate every cache
  // (including the miss-classification shadows). Statistics are kept.
  void flush();

  // Dinero's end of run: copy back every dirty block towards memory (this
  // counts in bytes_to_memory). Call once after the last reference, before
  // reading statistics that should match Dinero IV's output.
  void finish();

  int level_count() const;  // 1..kMaxLevels
  bool has_cache(int level, CacheKind kind) const;
  // `level` is 1-based (1 = L1). Throws std::out_of_range when absent.
  const Stats& stats(int level, CacheKind kind) const;
  const CacheConfig& cache_config(int level, CacheKind kind) const;
  const HierarchyConfig& config() const;

  std::uint64_t references_skipped() const;    // dropped by skip_count
  std::uint64_t references_simulated() const;  // accepted, after skipping
  bool max_count_exceeded() const;
  // Trigger state, for Dinero's end-of-run warnings.
  bool trigger_toggled() const;
  bool discarding() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace nodetrace::cachesim
