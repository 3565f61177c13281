// dinero-wrap run / exec: the trace is decoded once per group of Dinero IV
// processes (at most one per core at a time) and each process is fed the
// records of its cache as din / extended din text.
#include <fmt/format.h>

#include <algorithm>
#include <iterator>
#include <memory>
#include <thread>

#include "nodetrace/cachesim/wrap/wrap.hpp"
#include "nodetrace/cachesim/dinero/address_width.hpp"
#include "nodetrace/base/error.hpp"
#include "nodetrace/formats/record/record_format.hpp"

namespace nodetrace::cachesim::wrap {

using formats::Record;
using formats::RecordBatch;
using formats::RecordForm;
using formats::Tag;

namespace {

constexpr std::size_t kFlushBytes = 1 << 16;

enum class Role : std::uint8_t { Single, High, Low, HighPerAnimationFrame };

// A cache Dinero IV simulates for one configuration.
struct Job {
  std::size_t config = 0;
  Role role = Role::Single;
  std::uint32_t split_level = 0;
  CacheGeometry geometry;
  std::uint64_t refs = 0;
  std::uint64_t fetches = 0;
  std::uint64_t misses = 0;  // HighPerAnimationFrame: the loads, summed over frames

  bool takes(Tag tag) const {
    switch (role) {
      case Role::Single: return true;
      case Role::Low: return tag >= split_level;
      case Role::High:
      case Role::HighPerAnimationFrame: return tag < split_level;
    }
    return false;
  }
};

// A job's process during one pass (HighPerAnimationFrame: one process per frame).
class RunningJob {
 public:
  RunningJob(Job& job, const WrapOptions& options, const TraceContext& context,
             const Configuration& config)
      : job_(job), options_(options), context_(context), config_(config) {
    if (job_.role != Role::HighPerAnimationFrame) start();
  }

  void begin_animation_frame(std::uint64_t animation_frame) {
    if (job_.role != Role::HighPerAnimationFrame) return;
    finish();
    frame_ = animation_frame;
  }

  void add(const char* line, std::size_t length) {
    if (!process_) start();
    buffer_.append(line, length);
    ++job_.refs;
    if (buffer_.size() >= kFlushBytes) flush();
  }

  void finish() {
    if (!process_) return;
    flush();
    const int status = process_->wait();
    if (status != 0) {
      throw WrapError(fmt::format("Dinero IV ('{}') failed with exit status {}: {}",
                                  process_->command(), status, process_->errors()));
    }
    if (stopped_reading_) {
      throw WrapError(fmt::format("Dinero IV ('{}') stopped reading its input before the end of "
                                  "the trace, and exited with status 0: {}",
                                  process_->command(), process_->errors()));
    }
    std::vector<DineroCacheStats> caches;
    try {
      caches = parse_dinero_output(process_->output());
    } catch (const base::FormatError& error) {
      throw WrapError(fmt::format("'{}': {}", process_->command(), error.what()));
    }
    process_.reset();
    const DineroCacheStats& cache = caches.front();
    job_.fetches += cache.demand_fetches;
    job_.misses += cache.demand_misses;
    if (job_.role == Role::HighPerAnimationFrame) {
      // Fully associative LRU: misses == distinct blocks exactly when they fit.
      const std::uint64_t capacity = config_.high_size / config_.block;
      if (cache.demand_misses > capacity) {
        throw base::UsageError(fmt::format(
            "{}: the high-level nodes (levels < {}) touched in animation frame {} do not fit the "
            "high-level cache: Dinero IV loads {} {}-byte blocks into a fully associative "
            "{}-byte cache (of a {}-byte total, low cache {} bytes) that holds {}; give a "
            "smaller --split-level or a larger --high-size",
            context_.source_name, job_.split_level, frame_, cache.demand_misses, config_.block,
            config_.high_size, config_.size, config_.low_size, capacity));
      }
    }
  }

 private:
  void start() {
    std::vector<std::string> argv = options_.dinero;
    CacheGeometry geometry = job_.geometry;
    for (auto& argument :
         dinero_cache_arguments(context_.form, geometry, config_.fetch, config_.prefetch_distance)) {
      argv.push_back(std::move(argument));
    }
    process_ = std::make_unique<ChildProcess>(argv, ChildProcess::Output::Captured);
    stopped_reading_ = false;
  }

  void flush() {
    if (process_ && !buffer_.empty() && !stopped_reading_) stopped_reading_ = !process_->write(buffer_);
    buffer_.clear();
  }

  Job& job_;
  const WrapOptions& options_;
  const TraceContext& context_;
  const Configuration& config_;
  std::unique_ptr<ChildProcess> process_;
  bool stopped_reading_ = false;  // the process closed its input early
  std::string buffer_;
  std::uint64_t frame_ = 0;
};

unsigned jobs_at_a_time(const WrapOptions& options) {
  if (options.jobs > 0) return options.jobs;
  return std::max(1u, std::thread::hardware_concurrency());
}

}  // namespace

TraceResult wrap_run(const std::string& path, const std::vector<Configuration>& configs,
                     const std::string& trace_column, bool per_level, const WrapOptions& options,
                     bool per_animation_frame) {
  if (per_level) {
    throw base::UsageError(
        "--per-level: Dinero IV reports no counts per node level; use cachesim run for the "
        "per-level table");
  }
  if (per_animation_frame) {
    throw base::UsageError(
        "--per-frame: Dinero IV reports totals only, and its low caches are not flushed between "
        "animation frames; use cachesim run for the per-frame table");
  }
  // Planning: the header and the first batch (its marker gives K = auto).
  auto reader = formats::TraceReader::open(path, options.reader);
  const TraceContext context = trace_context(*reader, trace_column);
  RecordBatch first_batch;
  const bool has_records = reader->next(first_batch);
  const bool needs_levels = has_split(configs);
  if (needs_levels && !context.tags_are_levels) throw_untagged_trace(context, "the split scheme");
  TraceResult result;
  std::vector<Job> jobs;
  // K per animation frame: the plan follows the first pass's markers; the
  // jobs of every pass re-resolve K at each marker.
  SplitLevelPlan plan(configs, context);
  plan.begin_animation_frame(first_batch.marker ? &*first_batch.marker : nullptr);
  for (std::size_t i = 0; i < configs.size(); ++i) {
    const Configuration& config = configs[i];
    if (config.scheme == Scheme::Single) {
      jobs.push_back({i, Role::Single, 0, {config.size, config.block, config.assoc, config.policy}});
      continue;
    }
    const std::uint32_t split_level = plan.current(i);
    if (config.high_policy == HighPolicy::Retain) {
      const auto blocks = static_cast<std::uint32_t>(config.high_size / config.block);
      jobs.push_back({i, Role::HighPerAnimationFrame, split_level,
                      {config.high_size, config.block, blocks, ReplacementPolicy::Lru}});
    } else {
      jobs.push_back({i, Role::High, split_level,
                      {config.high_size, config.block, config.high_assoc, config.policy}});
    }
    jobs.push_back({i, Role::Low, split_level,
                    {config.low_size, config.block, config.assoc, config.policy}});
  }

  // Standard input is read once, so then every process runs in the one pass.
  const std::size_t group_size =
      path == "-" ? std::max<std::size_t>(jobs.size(), 1) : jobs_at_a_time(options);
  std::uint64_t other_stream_records = 0;
  std::uint64_t beyond_32_bits = 0;
  for (std::size_t group_start = 0; group_start < jobs.size(); group_start += group_size) {
    const bool first_pass = group_start == 0;
    const std::size_t group_end = std::min(jobs.size(), group_start + group_size);
    if (!first_pass) {
      reader = formats::TraceReader::open(path, options.reader);
      if (!reader->next(first_batch)) break;
    } else if (!has_records) {
      break;
    }
    std::vector<std::unique_ptr<RunningJob>> running;
    for (std::size_t j = group_start; j < group_end; ++j) {
      running.push_back(
          std::make_unique<RunningJob>(jobs[j], options, context, configs[jobs[j].config]));
    }
    // Binary traces are fed as extended din text (dinero_cache_arguments says
    // -informat D); Dinero IV rounds a din address itself.
    const RecordForm fed_form = context.form == RecordForm::Din ? RecordForm::Din : RecordForm::ExtendedDin;
    char line[formats::kMaxFormattedRecord];
    RecordBatch& batch = first_batch;
    bool first_batch_of_pass = true;
    do {
      if (batch.marker) {
        if (first_pass && !first_batch_of_pass) plan.begin_animation_frame(&*batch.marker);
        for (std::size_t j = group_start; j < group_end; ++j) {
          const Configuration& config = configs[jobs[j].config];
          if (config.scheme == Scheme::Split) {
            jobs[j].split_level = simulated_split_level(config, &*batch.marker, context);
          }
        }
        for (auto& job : running) job->begin_animation_frame(batch.marker->frame);
      }
      first_batch_of_pass = false;
      for (std::size_t r = 0; r < batch.records.size(); ++r) {
        const Record& record = batch.records[r];
        const Tag tag = record.tag;
        if (is_other_stream(tag)) {
          other_stream_records += first_pass;
          continue;
        }
        if (needs_levels && !formats::is_level(tag)) {
          throw_untagged_record(context, batch.first_record + r + 1, "the split scheme routes");
        }
        if (first_pass) beyond_32_bits += records_beyond_32_bits({&record, 1}, context.form);
        const std::size_t length = formats::format_record(record, fed_form, formats::kDineroTextLayout, line);
        for (std::size_t j = group_start; j < group_end; ++j) {
          if (jobs[j].takes(tag)) running[j - group_start]->add(line, length);
        }
      }
    } while (reader->next(batch));
    for (auto& job : running) job->finish();
  }

  for (std::size_t i = 0; i < configs.size(); ++i) {
    const Configuration& config = configs[i];
    ResultRow row;
    row.trace = trace_column;
    row.config = config;
    for (const Job& job : jobs) {
      if (job.config != i) continue;
      row.refs += job.refs;
      row.fetches += job.fetches;
      switch (job.role) {
        case Role::Single:
          row.misses = job.misses;
          break;
        case Role::High:
          row.high_refs = job.refs;
          row.high_misses = job.misses;
          break;
        case Role::HighPerAnimationFrame:
          row.high_refs = job.refs;
          row.high_loads = job.misses;
          row.high_misses = config.count_loads ? job.misses : 0;
          break;
        case Role::Low:
          row.low_refs = job.refs;
          row.low_misses = job.misses;
          break;
      }
    }
    if (config.scheme == Scheme::Split) {
      row.split_level = plan.first(i);
      row.misses = row.high_misses + row.low_misses;
    }
    result.rows.push_back(row);
  }
  result.notes = plan.notes();
  result.other_stream_records = other_stream_records;
  if (other_stream_records > 0) {
    result.notes.push_back(other_streams_note(trace_column, other_stream_records));
  }
  if (beyond_32_bits > 0) result.notes.push_back(beyond_32_bits_note(trace_column, beyond_32_bits));
  return result;
}

ExecResult wrap_exec(const std::string& path, const std::vector<std::string>& arguments,
                     const WrapOptions& options) {
  // Dinero IV's own run: an empty input is what Dinero IV makes of it.
  formats::ReaderOptions reader_options = options.reader;
  reader_options.allow_empty = true;
  auto reader = formats::TraceReader::open(path, reader_options);
  RecordForm form = reader->form() == RecordForm::Din ? RecordForm::Din : RecordForm::ExtendedDin;
  std::vector<std::string> argv = options.dinero;
  // The records are written in the form Dinero IV is told to read (its
  // last -informat wins, as in its own parser); an unknown letter is left to
  // Dinero IV to reject.
  const auto informat = std::find(arguments.rbegin(), arguments.rend(), "-informat");
  if (informat == arguments.rend()) {
    argv.push_back("-informat");
    argv.push_back(form == RecordForm::Din ? "d" : "D");
  } else if (informat != arguments.rbegin()) {
    const std::string& letter = *std::prev(informat);
    if (letter == "d") form = RecordForm::Din;
    if (letter == "D") form = RecordForm::ExtendedDin;
    if (letter == "b") form = RecordForm::Binary;
  }
  argv.insert(argv.end(), arguments.begin(), arguments.end());
  ChildProcess process(argv, ChildProcess::Output::ErrorsInherited);
  RecordBatch batch;
  std::string buffer;
  char line[formats::kMaxFormattedRecord];
  bool reading = true;  // Dinero IV stops reading at -maxcount or on a bad option
  while (reading && reader->next(batch)) {
    for (const Record& record : batch.records) {
      buffer.append(line, formats::format_record(record, form, formats::kDineroTextLayout, line));
      if (buffer.size() >= kFlushBytes) {
        reading = process.write(buffer);
        buffer.clear();
        if (!reading) break;
      }
    }
  }
  if (reading) process.write(buffer);
  ExecResult result;
  result.status = process.wait();
  result.output = process.output();
  return result;
}

}  // namespace nodetrace::cachesim::wrap
