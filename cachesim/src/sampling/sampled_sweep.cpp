// run_sampled_sweep: windows of the trace and groups of cache sets as the
// units of SAMPLING.md. Simulation runs on the calling thread (the reader
// decodes on its own threads); the chosen units depend on the seed alone.
#include <fmt/format.h>

#include <algorithm>
#include <memory>

#include "nodetrace/cachesim/sampling/sampled_sweep.hpp"
#include "nodetrace/base/error.hpp"
#include "nodetrace/base/sample_rate.hpp"

namespace nodetrace::cachesim {

using base::UsageError;

namespace {

// The residue of the sampled sets: drawn apart from the windows' hashes.
constexpr std::uint64_t kSetStream = 0x5e75e75e75e75e75ULL;

bool is_power_of_two(std::uint64_t value) { return value != 0 && (value & (value - 1)) == 0; }

// Sets of the caches a set filter must respect: the single / low cache and
// the high cache under `cache` (`retain` keeps whole blocks, not sets).
struct CacheSets {
  std::string what;
  std::uint64_t sets = 0;
};

std::vector<CacheSets> cache_sets(const Configuration& config) {
  std::vector<CacheSets> caches;
  auto sets = [&](std::uint64_t size, std::uint32_t ways) {
    return size / (std::uint64_t{config.block} * std::max<std::uint32_t>(ways, 1));
  };
  if (config.scheme == Scheme::Single) {
    caches.push_back({fmt::format("the {}-byte cache", config.size), sets(config.size, config.assoc)});
  } else {
    caches.push_back(
        {fmt::format("the {}-byte low cache", config.low_size), sets(config.low_size, config.assoc)});
    if (config.high_policy == HighPolicy::Cache) {
      caches.push_back({fmt::format("the {}-byte high cache", config.high_size),
                        sets(config.high_size, config.high_assoc)});
    }
  }
  return caches;
}

// How many set groups (a power of two, at most kMaxSetGroups) every cache
// can be cut into with `every`: the groups' blocks must never share a set.
std::uint64_t set_groups(const std::vector<Configuration>& configs, std::uint64_t every) {
  if (!is_power_of_two(every)) {
    throw UsageError(fmt::format(
        "--sample-sets 1/{}: K must be a power of two (set counts are, and block number mod K "
        "picks whole sets only when K divides them)",
        every));
  }
  std::uint64_t fewest_sets = UINT64_MAX;
  for (const Configuration& config : configs) {
    if (config.block != configs.front().block) {
      throw UsageError("--sample-sets: the configurations must share one --block (the set of a "
                       "block number depends on the block size)");
    }
    for (const CacheSets& cache : cache_sets(config)) {
      if (!is_power_of_two(cache.sets) || cache.sets < every) {
        throw UsageError(fmt::format(
            "--sample-sets 1/{}: {} (block {}) has {} set(s); set sampling needs a power-of-two "
            "number of sets, at least {} (a fully associative cache has one set)",
            every, cache.what, config.block, cache.sets, every));
      }
      fewest_sets = std::min(fewest_sets, cache.sets);
    }
  }
  std::uint64_t groups = 1;
  while (groups < kMaxSetGroups && groups * 2 * every <= fewest_sets) groups *= 2;
  return groups;
}

struct SampleUnit {
  std::vector<SampleUnitCounts> per_config;
};

// Adds one sweep's counts since `before` (empty: since its start); a sweep
// that has seen no batch yet has no counts and adds nothing.
void add_since(SampleUnit& unit, const std::vector<ResultRow>& now, const std::vector<ResultRow>& before) {
  if (now.empty()) return;
  unit.per_config.resize(now.size());
  for (std::size_t c = 0; c < now.size(); ++c) {
    const std::uint64_t fetches = before.empty() ? 0 : before[c].fetches;
    const std::uint64_t misses = before.empty() ? 0 : before[c].misses;
    unit.per_config[c].fetches += now[c].fetches - fetches;
    unit.per_config[c].misses += now[c].misses - misses;
  }
}

// The sweeps of a sampled run (one per set group) and the per-unit counts.
class SampledRun {
 public:
  // `rows`: the trace's header "sampling" (its windows are its markers).
  SampledRun(const std::vector<Configuration>& configs, const TraceContext& context,
             const SamplingOptions& options, const std::optional<formats::SamplingInfo>& rows)
      : configs_(configs), options_(options), rows_(rows), trace_(context.trace), source_name_(context.source_name),
        form_(context.form) {
    if (options.window_records == 0) throw UsageError("--window-records: must be at least 1");
    if (rows_ && options.window_every != 0) {
      throw UsageError(fmt::format(
          "--sample-windows: {} is already sampled ({} 1/{} in its header \"sampling\"); its "
          "windows are the ones its markers begin",
          context.source_name, rows_->method, rows_->every));
    }
    for (const Configuration& config : configs) {
      // MIN needs every fetch of the run; brrip's insertion counter and
      // drrip's selector are shared by all sets, so sets sampled apart
      // would not see the whole cache's.
      if (config.policy == ReplacementPolicy::Opt) {
        throw UsageError(fmt::format("--policy opt: not with sampling ({}): MIN needs every fetch of the "
                                     "cache; simulate the whole trace",
                                     rows_ ? context.source_name + " is row-sampled" : "--sample-windows, "
                                     "--sample-sets"));
      }
      if (options.set_every != 0 &&
          (config.policy == ReplacementPolicy::Brrip || config.policy == ReplacementPolicy::Drrip)) {
        throw UsageError(fmt::format("--policy {} with --sample-sets: its insertion counter (and drrip's "
                                     "selector) belong to the whole cache; allowed with --sample-sets: lru, "
                                     "fifo, plru, srrip (or use --sample-windows)",
                                     policy_name(config.policy)));
      }
      // Each group of sets would draw its own sequence, not the whole cache's.
      if (options.set_every != 0 && config.policy == ReplacementPolicy::Random) {
        throw UsageError("--policy random with --sample-sets: its draws (Dinero IV's one sequence per cache) "
                         "belong to the whole cache; allowed with --sample-sets: lru, fifo, plru, srrip (or use "
                         "--sample-windows)");
      }
    }
    if (options.set_every != 0) {
      groups_ = set_groups(configs, options.set_every);
      residue_ = base::mix64(options.seed ^ kSetStream) % options.set_every;
    }
    for (std::uint64_t g = 0; g < groups_; ++g) {
      sweeps_.push_back(std::make_unique<Sweep>(configs, context, false));
    }
    group_batches_.resize(groups_);
  }

  bool window_chosen(std::uint64_t window) const {
    return cachesim::window_chosen(options_, window);
  }

  void feed(const formats::RecordBatch& batch) {
    end_ = std::max(end_, batch.first_record + batch.records.size());
    if (rows_) {
      feed_marked(batch);
      return;
    }
    if (batch.records.empty()) {
      if (batch.marker) feed_piece(batch, 0, 0, false);  // an empty animation frame
      return;
    }
    std::size_t begin = 0;
    while (begin < batch.records.size()) {
      const std::uint64_t record = batch.first_record + begin;
      const std::uint64_t window = record / options_.window_records;
      const std::uint64_t window_end = (window + 1) * options_.window_records;
      const std::size_t end = static_cast<std::size_t>(
          std::min<std::uint64_t>(batch.records.size(), begin + (window_end - record)));
      if (!window_open_ || window != open_window_) {
        close_window();
        open_window(window, window_chosen(window));
      }
      feed_piece(batch, begin, end, open_chosen_);
      begin = end;
    }
  }

  SampledResult finish(std::uint64_t total_records) {
    close_window();
    std::vector<TraceResult> results;
    for (auto& sweep : sweeps_) results.push_back(sweep->finish());
    SampledResult out;
    total_records = std::max(total_records, end_);
    double domain_fraction = 1.0;  // of the full render, for a row-sampled trace
    if (rows_) {
      // Every band of every animation frame the trace was rendered from.
      out.windows = std::max(windows_simulated_, rows_->bands * std::max<std::uint64_t>(frames_, 1));
      domain_fraction = out.windows == 0 ? 1.0
                                         : static_cast<double>(windows_simulated_) /
                                               static_cast<double>(out.windows);
    } else {
      out.windows = (total_records + options_.window_records - 1) / options_.window_records;
    }
    out.windows_simulated = windows_simulated_;
    if (records_simulated_ == 0 && total_records > 0) throw_nothing_simulated(total_records, out.windows);
    // The units and how many there are in all.
    std::vector<SampleUnit> units;
    std::uint64_t population = 0;
    SampleDesign design = SampleDesign::Stratified;
    if (options_.set_every != 0) {
      design = SampleDesign::Random;
      for (const TraceResult& result : results) {
        SampleUnit unit;
        add_since(unit, result.rows, {});
        units.push_back(std::move(unit));
      }
      const std::uint64_t window_every =
          rows_ ? std::max<std::uint64_t>(rows_->every, 1)
                : (options_.window_every != 0 ? options_.window_every : 1);
      population = groups_ * options_.set_every * window_every;
    } else {
      units = window_units_;
      population = out.windows;
    }
    const double fraction =
        domain_fraction *
        (total_records == 0 ? 1.0
                            : static_cast<double>(records_simulated_) / static_cast<double>(total_records));
    auto unit_column = [&](std::size_t config) {
      std::vector<SampleUnitCounts> column;
      for (const SampleUnit& unit : units) {
        column.push_back(unit.per_config.empty() ? SampleUnitCounts{} : unit.per_config[config]);
      }
      return column;
    };
    // Rows: the groups' counts summed.
    for (std::size_t c = 0; c < configs_.size(); ++c) {
      ResultRow row = results[0].rows[c];
      for (std::size_t g = 1; g < results.size(); ++g) {
        const ResultRow& more = results[g].rows[c];
        row.refs += more.refs;
        row.fetches += more.fetches;
        row.misses += more.misses;
        row.high_refs += more.high_refs;
        row.high_misses += more.high_misses;
        if (row.high_loads) *row.high_loads += more.high_loads.value_or(0);
        row.low_refs += more.low_refs;
        row.low_misses += more.low_misses;
      }
      out.rows.push_back(SampledRow{row, fraction, ratio_estimate(unit_column(c), population, design)});
    }
    for (std::size_t c = 0; c < configs_.size(); ++c) {
      const Configuration& split = configs_[c];
      if (split.scheme != Scheme::Split) continue;
      for (std::size_t s = 0; s < configs_.size(); ++s) {
        const Configuration& single = configs_[s];
        if (single.scheme != Scheme::Single || single.size != split.size ||
            single.block != split.block || single.assoc != split.assoc ||
            single.policy != split.policy) {
          continue;
        }
        out.gains.push_back(GainRow{out.rows[c].row, out.rows[s].row, fraction,
                                    gain_estimate(unit_column(s), unit_column(c), population, design)});
        break;
      }
    }
    out.notes = results[0].notes;
    if (units.size() < 2 && population > units.size()) {
      out.notes.push_back(fmt::format("{}: fewer than two sampled units: no error estimate",
                                      configs_.empty() ? "" : results[0].rows[0].trace));
    }
    return out;
  }

 private:
  // A sample of no records has no miss ratio: rather than a report of empty
  // rows and exit 0, an error (exit 1) that says why and what to change.
  [[noreturn]] void throw_nothing_simulated(std::uint64_t total_records, std::uint64_t windows) const {
    std::string why;
    if (options_.window_every != 0 && windows_simulated_ == 0) {
      // A trace shorter than a window is one window of all its records.
      const std::string drawn_from =
          windows == 1 ? fmt::format("1 window (all {} records; a window is {} records)", total_records,
                                     options_.window_records)
                       : fmt::format("{} windows of {} records", windows, options_.window_records);
      why = fmt::format("--sample-windows 1/{} drew none of its {}: give a smaller K or shorter windows "
                        "(--window-records)",
                        options_.window_every, drawn_from);
    } else if (options_.set_every != 0) {
      why = fmt::format("--sample-sets 1/{}: no record falls in the sampled sets: give a smaller K",
                        options_.set_every);
    } else {
      why = "no window of the row-sampled trace holds a record";
    }
    throw base::FormatError(
        fmt::format("{}: the sample simulated none of the trace's {} records: {}", trace_, total_records, why));
  }

  // A row-sampled trace: a window marker begins a window, an animation-frame
  // marker ends it (records before any window marker are a window too).
  void feed_marked(const formats::RecordBatch& batch) {
    if (batch.marker) {
      close_window();
      window_open_ = false;
      ++frames_;
    }
    if (batch.window) {
      close_window();
      open_window(marked_windows_++, true);
    } else if (!window_open_ && !batch.records.empty()) {
      open_window(marked_windows_++, true);
    }
    feed_piece(batch, 0, batch.records.size(), window_open_);
  }

  void open_window(std::uint64_t window, bool chosen) {
    window_open_ = true;
    open_window_ = window;
    open_chosen_ = chosen;
    if (!chosen) return;
    ++windows_simulated_;
    at_window_start_.clear();
    for (auto& sweep : sweeps_) at_window_start_.push_back(sweep->counts());
  }

  void close_window() {
    if (!window_open_ || !open_chosen_) return;
    open_chosen_ = false;
    SampleUnit unit;
    for (std::size_t g = 0; g < sweeps_.size(); ++g) {
      add_since(unit, sweeps_[g]->counts(), at_window_start_[g]);
    }
    window_units_.push_back(std::move(unit));
  }

  // Records [begin, end) of `batch`, all in one window, simulated when it
  // is `chosen` (the marker only goes with the piece at records[0]).
  void feed_piece(const formats::RecordBatch& batch, std::size_t begin, std::size_t end,
                  bool chosen) {
    const bool marker = begin == 0 && batch.marker.has_value();
    chosen = chosen && end > begin;
    if (!chosen && !marker) return;
    if (options_.set_every == 0) {
      if (chosen) records_simulated_ += end - begin;
      if (chosen && begin == 0 && end == batch.records.size()) {
        sweeps_[0]->feed(batch);  // a whole batch: no copy
        return;
      }
      formats::RecordBatch& piece = group_batches_[0];
      piece.marker = marker ? batch.marker : std::nullopt;
      piece.first_record = batch.first_record + begin;
      piece.records.clear();
      if (chosen) {
        piece.records.assign(batch.records.begin() + static_cast<std::ptrdiff_t>(begin),
                             batch.records.begin() + static_cast<std::ptrdiff_t>(end));
      }
      sweeps_[0]->feed(piece);
      return;
    }
    for (formats::RecordBatch& piece : group_batches_) {
      piece.marker = marker ? batch.marker : std::nullopt;
      piece.first_record = batch.first_record + begin;
      piece.records.clear();
    }
    if (chosen) {  // one pass routes each sampled record to its group
      const std::uint64_t block_size = configs_.front().block;
      for (std::size_t i = begin; i < end; ++i) {
        const std::uint64_t block = batch.records[i].address / block_size;
        refuse_spanning_reference(batch.records[i], block_size, batch.first_record + i + 1);
        if (block % options_.set_every != residue_) continue;
        group_batches_[(block / options_.set_every) % groups_].records.push_back(batch.records[i]);
      }
    }
    for (std::uint64_t g = 0; g < groups_; ++g) {
      formats::RecordBatch& piece = group_batches_[g];
      records_simulated_ += piece.records.size();
      if (piece.marker || !piece.records.empty()) sweeps_[g]->feed(piece);
    }
  }

  // A reference whose blocks lie in two sets is routed whole, so set
  // sampling would count it in one set's group only: refused, naming it.
  // An invalidation acts on its address's block alone and a copy-back
  // changes no count, so neither spans.
  void refuse_spanning_reference(const formats::Record& record, std::uint64_t block_size,
                                 std::uint64_t record_number) const {
    if (record.type == formats::AccessType::Invalidate || record.type == formats::AccessType::CopyBack ||
        is_other_stream(record.tag)) {
      return;
    }
    const formats::Record view = formats::dinero_view(record, form_);
    const std::uint64_t last = view.address + (view.size == 0 ? 0 : view.size - 1);
    if (view.address / block_size == last / block_size && last >= view.address) return;
    throw base::FormatError(fmt::format(
        "{}: record {}: --sample-sets: the reference at 0x{:x} of {} bytes spans blocks of {} bytes, which lie in "
        "different sets, and set sampling routes a reference whole: use --sample-windows, or a block that holds "
        "each reference",
        source_name_, record_number, view.address, view.size, block_size));
  }

  const std::vector<Configuration>& configs_;
  SamplingOptions options_;
  std::uint64_t groups_ = 1;
  std::uint64_t residue_ = 0;
  std::vector<std::unique_ptr<Sweep>> sweeps_;
  std::vector<formats::RecordBatch> group_batches_;
  std::optional<formats::SamplingInfo> rows_;
  std::string trace_;  // the report's trace column
  std::string source_name_;
  formats::RecordForm form_;
  bool window_open_ = false;
  bool open_chosen_ = false;
  std::uint64_t open_window_ = 0;
  std::uint64_t marked_windows_ = 0;  // row-sampled: windows begun
  std::uint64_t frames_ = 0;          // row-sampled: animation-frame markers
  std::vector<std::vector<ResultRow>> at_window_start_;
  std::vector<SampleUnit> window_units_;
  std::uint64_t windows_simulated_ = 0;
  std::uint64_t records_simulated_ = 0;
  std::uint64_t end_ = 0;
};

std::uint64_t trailer_records(const formats::TraceReader& reader) {
  const auto& trailer = reader.trailer();
  if (!trailer || trailer->index.empty()) return 0;
  const formats::DataFrameIndexEntry& last = trailer->index.back();
  return last.first_record + last.record_count;
}

}  // namespace

std::uint64_t chosen_in_stratum(std::uint64_t seed, std::uint64_t stratum, std::uint64_t every) {
  return base::mix64(base::mix64(seed) ^ stratum) % every;
}

bool window_chosen(const SamplingOptions& options, std::uint64_t window) {
  const std::uint64_t every = options.window_every;
  if (every <= 1) return true;
  return chosen_in_stratum(options.seed, window / every, every) == window % every;
}

bool records_chosen(const SamplingOptions& options, std::uint64_t first, std::uint64_t count) {
  if (count == 0) return false;
  const std::uint64_t first_window = first / options.window_records;
  const std::uint64_t last_window = (first + count - 1) / options.window_records;
  // Every whole stratum holds a chosen window: at most 2 K windows to look at.
  if (options.window_every <= 1 || last_window - first_window >= 2 * options.window_every) {
    return true;
  }
  for (std::uint64_t w = first_window; w <= last_window; ++w) {
    if (window_chosen(options, w)) return true;
  }
  return false;
}

std::function<bool(const formats::DataFrameIndexEntry&)> data_frame_filter(const SamplingOptions& options) {
  return [options](const formats::DataFrameIndexEntry& entry) {
    return records_chosen(options, entry.first_record, entry.record_count);
  };
}

class FedSampledSweep::Run : public SampledRun {
  using SampledRun::SampledRun;
};

FedSampledSweep::FedSampledSweep(const formats::TraceReader& source, const std::vector<Configuration>& configs,
                                 const std::string& trace_column, const SamplingOptions& options)
    : source_(source) {
  const std::optional<formats::SamplingInfo> rows = source.header().sampling();
  run_ = std::make_unique<Run>(configs, trace_context(source, trace_column), options, rows);
}

FedSampledSweep::~FedSampledSweep() = default;

void FedSampledSweep::feed(const formats::RecordBatch& batch) { run_->feed(batch); }

SampledResult FedSampledSweep::finish() { return run_->finish(trailer_records(source_)); }

SampledResult run_sampled_sweep(formats::TraceReader& reader,
                                const std::vector<Configuration>& configs,
                                const std::string& trace_column, const SamplingOptions& options) {
  FedSampledSweep run(reader, configs, trace_column, options);
  formats::RecordBatch batch;
  while (reader.next(batch)) run.feed(batch);
  return run.finish();
}

}  // namespace nodetrace::cachesim
