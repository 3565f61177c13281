// The cache hierarchy: configuration checks, wiring of the caches the way
// Dinero IV wires them, and Dinero's main loop (skip, triggers, maximum,
// flush) around each reference.
#include "nodetrace/cachesim/dinero/engine.hpp"

#include <fmt/format.h>

#include <bit>
#include <stdexcept>
#include <string>

#include "dinero/engine_cache.hpp"
#include "nodetrace/base/error.hpp"

namespace nodetrace::cachesim {

namespace {


std::string cache_name(int level, int kind) {
  return fmt::format("l{}-{}cache", level, cache_kind_letter(kind));
}

const std::optional<CacheConfig>& level_cache(const LevelConfig& level, int kind) {
  switch (kind) {
    case 0: return level.unified;
    case 1: return level.instruction;
    default: return level.data;
  }
}

// The shared geometry checks, then what only Dinero's caches have.
void validate_cache(const CacheConfig& c, const std::string& name) {
  validate_geometry(c.geometry(), name);
  auto fail = [&](const std::string& what) { throw base::UsageError(name + ": " + what); };
  const std::uint32_t sub = c.effective_sub_block_size();
  if (!std::has_single_bit(sub)) fail(fmt::format("sub-block size {} is not a power of two", sub));
  if (sub > c.block_size) {
    fail(fmt::format("sub-block size {} is larger than the block size {}", sub, c.block_size));
  }
  if (c.block_size / sub > 32) {
    fail(fmt::format("{} sub-blocks per block; at most 32 are allowed", c.block_size / sub));
  }
  if (sub > 32768) fail(fmt::format("sub-block size {} is above 32768", sub));
  if (c.prefetch_abort > 100) fail(fmt::format("prefetch abort percentage {} is above 100", c.prefetch_abort));
  if ((c.fetch == FetchPolicy::LoadForward || c.fetch == FetchPolicy::SubBlock) &&
      c.prefetch_distance > c.block_size / sub) {
    fail(fmt::format("prefetch distance {} sub-blocks is more than the {} of a block", c.prefetch_distance,
                     c.block_size / sub));
  }
  // Each block costs a few dozen bytes of simulator memory (twice with ccc).
  constexpr std::uint64_t kMaxBlocks = std::uint64_t{1} << 26;
  const std::uint64_t blocks = c.size / c.block_size;
  if (blocks > kMaxBlocks) {
    fail(fmt::format("{} blocks are more than this simulator holds (at most {})", blocks, kMaxBlocks));
  }
}

}  // namespace

FetchCounts& FetchCounts::operator+=(const FetchCounts& other) {
  auto add = [](PerType& a, const PerType& b) {
    for (std::size_t i = 0; i < a.size(); ++i) a[i] += b[i];
  };
  add(fetches, other.fetches);
  add(misses, other.misses);
  add(block_misses, other.block_misses);
  add(compulsory, other.compulsory);
  add(capacity, other.capacity);
  add(conflict, other.conflict);
  add(compulsory_block, other.compulsory_block);
  add(capacity_block, other.capacity_block);
  add(conflict_block, other.conflict_block);
  return *this;
}

Stats& Stats::operator+=(const Stats& other) {
  FetchCounts::operator+=(other);
  prefetch += other.prefetch;
  multi_block_refs += other.multi_block_refs;
  bytes_from_memory += other.bytes_from_memory;
  bytes_to_memory += other.bytes_to_memory;
  return *this;
}

void HierarchyConfig::validate() const {
  if (levels.empty()) throw base::UsageError("no cache level is configured");
  if (levels.size() > static_cast<std::size_t>(kMaxLevels)) {
    throw base::UsageError(
        fmt::format("{} cache levels configured; at most {} are allowed", levels.size(), kMaxLevels));
  }
  for (std::size_t i = 0; i < levels.size(); ++i) {
    const LevelConfig& level = levels[i];
    const int number = static_cast<int>(i) + 1;
    if (!level.unified && !level.instruction && !level.data) {
      throw base::UsageError(fmt::format("no level {} cache specified", number));
    }
    if (level.unified && (level.instruction || level.data)) {
      throw base::UsageError(
          fmt::format("level {} has i or d together with u cache parameters", number));
    }
    if (i > 0 && levels[i - 1].unified && !level.unified) {
      throw base::UsageError(
          fmt::format("level {} cache is unified, level {} is not", number - 1, number));
    }
    for (int kind = 0; kind < 3; ++kind) {
      if (const auto& cache = level_cache(level, kind)) validate_cache(*cache, cache_name(number, kind));
    }
  }
}

HierarchyConfig single_level(const CacheConfig& cache, CacheKind kind) {
  HierarchyConfig config;
  LevelConfig level;
  switch (kind) {
    case CacheKind::Unified: level.unified = cache; break;
    case CacheKind::Instruction: level.instruction = cache; break;
    case CacheKind::Data: level.data = cache; break;
  }
  config.levels.push_back(level);
  return config;
}

struct Hierarchy::Impl {
  HierarchyConfig config;
  detail::LibcRandom random;  // Dinero IV's one random() sequence, for every cache
  std::vector<std::unique_ptr<detail::Cache>> storage;
  std::array<std::array<detail::Cache*, 3>, kMaxLevels> caches{};
  detail::Cache* instruction_side = nullptr;  // where instruction fetches go; nullptr: memory
  detail::Cache* data_side = nullptr;
  std::uint64_t skipped = 0;
  std::uint64_t simulated = 0;
  std::uint64_t until_flush = 0;
  std::uint64_t until_stats = 0;
  bool exceeded = false;
  bool discard = false;
  bool toggled = false;

  void send(detail::Cache* cache, const detail::Ref& ref) {
    if (cache != nullptr) cache->ref(ref);
  }

  void simulate(const formats::Record& record) {
    detail::Ref ref;
    ref.address = record.address & detail::kAddressMask;
    ref.size = static_cast<std::uint16_t>(record.size);  // Dinero's sizes are 16 bits
    ref.type = static_cast<std::uint8_t>(record.type);
    switch (record.type) {
      case formats::AccessType::InstructionFetch:
        send(instruction_side, ref);
        break;
      case formats::AccessType::Invalidate:
        send(instruction_side, ref);
        send(data_side, ref);
        break;
      default:
        send(data_side, ref);
        break;
    }
  }

  void flush() {
    detail::Ref ref;
    ref.type = detail::kCopyBack;
    send(data_side, ref);
    ref.type = detail::kInvalidate;
    send(instruction_side, ref);
    if (instruction_side != data_side) send(data_side, ref);
  }
};

Hierarchy::Hierarchy(const HierarchyConfig& config) : impl_(std::make_unique<Impl>()) {
  config.validate();
  impl_->config = config;
  // Built from memory upwards, as Dinero's initialize_caches does.
  detail::Cache* instruction_side = nullptr;
  detail::Cache* data_side = nullptr;
  for (int i = static_cast<int>(config.levels.size()) - 1; i >= 0; --i) {
    for (int kind = 0; kind < 3; ++kind) {
      const auto& cache_config = level_cache(config.levels[i], kind);
      if (!cache_config) continue;
      auto cache = std::make_unique<detail::Cache>(*cache_config, impl_->random);
      detail::Cache* c = cache.get();
      impl_->storage.push_back(std::move(cache));
      impl_->caches[i][kind] = c;
      if (kind == 0) {
        c->downstream = instruction_side;
        instruction_side = data_side = c;
      } else if (kind == 1) {
        c->downstream = instruction_side;
        instruction_side = c;
      } else {
        c->downstream = data_side;
        data_side = c;
      }
    }
  }
  impl_->instruction_side = instruction_side;
  impl_->data_side = data_side;
  impl_->until_flush = config.flush_count;
  impl_->until_stats = config.stat_interval;
  impl_->discard = config.on_trigger != 0;
}

Hierarchy::~Hierarchy() = default;
Hierarchy::Hierarchy(Hierarchy&&) noexcept = default;
Hierarchy& Hierarchy::operator=(Hierarchy&&) noexcept = default;

bool Hierarchy::access(const formats::Record& record) {
  Impl& s = *impl_;
  const HierarchyConfig& c = s.config;
  if (s.skipped < c.skip_count) {
    ++s.skipped;
    return true;
  }
  if (s.exceeded) return false;
  // Dinero IV compares its 32-bit address with the triggers' 64 bits.
  const std::uint64_t address = record.address & detail::kAddressMask;
  if (address != 0 && (c.on_trigger != 0 || c.off_trigger != 0)) {
    if ((s.discard && c.on_trigger == address) || (!s.discard && c.off_trigger == address)) {
      s.discard = !s.discard;
      s.toggled = true;
      return true;
    }
  }
  if (s.discard) return true;
  if (c.max_count != 0 && s.simulated >= c.max_count) {
    s.exceeded = true;
    return false;
  }
  s.simulate(record);
  ++s.simulated;
  if (s.until_stats > 0 && --s.until_stats == 0) {
    if (c.on_stat_interval) c.on_stat_interval(*this);
    s.until_stats = c.stat_interval;
  }
  if (s.until_flush > 0 && --s.until_flush == 0) {
    s.flush();
    s.until_flush = c.flush_count;
  }
  return true;
}

std::size_t Hierarchy::access_batch(std::span<const formats::Record> records,
                                    formats::RecordForm form) {
  const HierarchyConfig& c = impl_->config;
  if (c.skip_count == 0 && c.max_count == 0 && c.flush_count == 0 && c.stat_interval == 0 &&
      c.on_trigger == 0 && c.off_trigger == 0) {
    // Nothing to count between references: the tight loop.
    Impl& s = *impl_;
    for (const formats::Record& record : records) s.simulate(formats::dinero_view(record, form));
    s.simulated += records.size();
    return records.size();
  }
  std::size_t consumed = 0;
  for (const formats::Record& record : records) {
    if (!access(formats::dinero_view(record, form))) break;
    ++consumed;
  }
  return consumed;
}

void Hierarchy::flush() { impl_->flush(); }

void Hierarchy::finish() {
  detail::Ref ref;
  ref.type = detail::kCopyBack;
  impl_->send(impl_->data_side, ref);
}

int Hierarchy::level_count() const { return static_cast<int>(impl_->config.levels.size()); }

bool Hierarchy::has_cache(int level, CacheKind kind) const {
  if (level < 1 || level > level_count()) return false;
  return impl_->caches[level - 1][static_cast<int>(kind)] != nullptr;
}

const Stats& Hierarchy::stats(int level, CacheKind kind) const {
  if (!has_cache(level, kind)) {
    throw std::out_of_range(fmt::format("no cache {} in this hierarchy",
                                        cache_name(level, static_cast<int>(kind))));
  }
  return impl_->caches[level - 1][static_cast<int>(kind)]->stats;
}

const CacheConfig& Hierarchy::cache_config(int level, CacheKind kind) const {
  if (!has_cache(level, kind)) {
    throw std::out_of_range(fmt::format("no cache {} in this hierarchy",
                                        cache_name(level, static_cast<int>(kind))));
  }
  return *level_cache(impl_->config.levels[level - 1], static_cast<int>(kind));
}

const HierarchyConfig& Hierarchy::config() const { return impl_->config; }
std::uint64_t Hierarchy::references_skipped() const { return impl_->skipped; }
std::uint64_t Hierarchy::references_simulated() const { return impl_->simulated; }
bool Hierarchy::max_count_exceeded() const { return impl_->exceeded; }
bool Hierarchy::trigger_toggled() const { return impl_->toggled; }
bool Hierarchy::discarding() const { return impl_->discard; }

}  // namespace nodetrace::cachesim
