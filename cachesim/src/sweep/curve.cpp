#include "nodetrace/cachesim/sweep/curve.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <memory>

#include "nodetrace/cachesim/models/lru_stack.hpp"
#include "nodetrace/cachesim/report/report.hpp"
#include "nodetrace/cachesim/sweep/sweep.hpp"
#include "nodetrace/base/error.hpp"
#include "models/opt_cache.hpp"
#include "models/opt_curve.hpp"
#include "models/record_blocks.hpp"

namespace nodetrace::cachesim {

using formats::AccessType;
using formats::Record;
using base::UsageError;

namespace {

// The records one block size's caches see: all (single), or those of levels
// >= K of the current animation frame (the split scheme's low cache).
struct Stream {
  Scheme scheme = Scheme::Single;
  std::uint32_t block = 8;
  Configuration k_rule;  // split: how K is found per frame
  std::uint32_t split_level = 0;
  std::uint32_t first_split_level = 0;
  bool started = false;
  std::vector<std::size_t> points;  // indices of its set-associative points
  std::unique_ptr<Sweep> sweep;     // those points as single caches
  std::unique_ptr<LruStack> stack;  // lru, assoc full
  LruSizeCurve full;
  std::uint64_t full_fetches = 0;
  std::unique_ptr<OptStream> opt;  // every opt point's fetches
  std::uint64_t opt_fetches = 0;
  formats::RecordBatch low_batch;
};

void feed_stack(Stream& stream, const Record& record, formats::RecordForm form,
                const TraceContext& context, std::uint64_t record_number) {
  if (record.type == AccessType::Invalidate && stream.stack) {
    throw UsageError(fmt::format(
        "{}: record {}: --curve with --assoc full answers every LRU size with one LRU stack, which "
        "has no invalidate; give numeric associativities for this trace",
        context.source_name, record_number));
  }
  const bool invalidate = record.type == AccessType::Invalidate;
  if (record.type > AccessType::Misc && !invalidate) return;  // copy-back: not a demand fetch
  const BlockRange blocks =
      blocks_of(record, form, static_cast<unsigned>(std::countr_zero(stream.block)), false);
  for (std::uint64_t block = blocks.first;; block = blocks.after(block)) {
    if (stream.opt) {
      if (invalidate) {
        stream.opt->invalidate(block);
      } else {
        ++stream.opt_fetches;
        stream.opt->fetch(block);
      }
    }
    if (stream.stack) {
      ++stream.full_fetches;
      stream.full.count(stream.stack->access(block));
    }
    if (block == blocks.last) break;
  }
}

// The opt points of `stream` from its kept fetches.
void settle_opt(const Stream& stream, std::vector<CurvePoint>& points) {
  const ChunkedArray next_uses = stream.opt->next_uses();
  unsigned layers = 0;
  for (const CurvePoint& point : points) {
    if (point.policy != ReplacementPolicy::Opt || point.scheme != stream.scheme || point.block != stream.block) {
      continue;
    }
    if (point.assoc == 0) {
      layers = std::max(layers, static_cast<unsigned>(std::countr_zero(point.size / point.block)) + 1);
    }
  }
  std::vector<std::uint64_t> full;
  if (layers > 0) full = opt_size_curve(*stream.opt, next_uses, layers);
  for (CurvePoint& point : points) {
    if (point.policy != ReplacementPolicy::Opt || point.scheme != stream.scheme || point.block != stream.block) {
      continue;
    }
    point.fetches = stream.opt_fetches;
    const std::uint64_t blocks = point.size / point.block;
    if (point.assoc == 0) {
      point.misses = full[static_cast<unsigned>(std::countr_zero(blocks))];
      continue;
    }
    point.misses = opt_misses(*stream.opt, next_uses, blocks / point.assoc, point.assoc);
  }
}

}  // namespace

std::vector<CurvePoint> run_curve(formats::TraceReader& reader, const CurveOptions& options,
                                  const std::string& trace_column) {
  const TraceContext context = trace_context(reader, trace_column);
  std::vector<CurvePoint> points;
  std::vector<Stream> streams;
  for (const Scheme scheme : options.schemes) {
    if (scheme == Scheme::Split) {
      if (!context.tags_are_levels) throw_untagged_trace(context, "the split scheme");
      if (!options.split_level && !options.high_size) {
        throw UsageError(
            "--curve: the split scheme's low cache needs K: give --split-level K, or --high-size "
            "for --split-level auto");
      }
    }
    for (const std::uint32_t block : options.blocks) {
      Stream& stream = streams.emplace_back();
      stream.scheme = scheme;
      stream.block = block;
      stream.k_rule.scheme = Scheme::Split;
      stream.k_rule.block = block;
      stream.k_rule.split_level = options.split_level;
      stream.k_rule.high_size = options.high_size.value_or(block);
      std::vector<Configuration> configs;
      for (const ReplacementPolicy policy : options.policies) {
        for (const std::uint32_t assoc : options.assocs) {
          if (assoc == 0 && policy != ReplacementPolicy::Lru && policy != ReplacementPolicy::Opt) {
            throw UsageError(fmt::format("--curve: --assoc full is answered for lru (one LRU stack) and opt "
                                         "(MIN's layered stack), not {}; give numeric associativities",
                                         policy_name(policy)));
          }
          const std::uint64_t smallest = std::uint64_t{block} * (assoc == 0 ? 1 : assoc);
          for (std::uint64_t size = smallest; size <= options.max_size; size *= 2) {
            CurvePoint point;
            point.trace = trace_column;
            point.scheme = scheme;
            point.block = block;
            point.assoc = assoc;
            point.policy = policy;
            point.size = size;
            if (assoc != 0) {
              validate_geometry({size, block, assoc, policy}, fmt::format("{}-byte cache", size));
            }
            if (policy == ReplacementPolicy::Opt) {
              if (!stream.opt) stream.opt = std::make_unique<OptStream>();
            } else if (assoc != 0) {
              Configuration config;
              config.size = size;
              config.block = block;
              config.assoc = assoc;
              config.policy = policy;
              configs.push_back(config);
              stream.points.push_back(points.size());
            } else if (!stream.stack) {
              stream.stack = std::make_unique<LruStack>();
            }
            points.push_back(point);
          }
        }
      }
      if (!configs.empty()) {
        TraceContext single_context = context;
        stream.sweep = std::make_unique<Sweep>(std::move(configs), single_context, false);
      }
    }
  }

  formats::RecordBatch batch;
  while (reader.next(batch)) {
    for (Stream& stream : streams) {
      if (stream.scheme == Scheme::Split && (batch.marker || !stream.started)) {
        stream.split_level = simulated_split_level(
            stream.k_rule, batch.marker ? &*batch.marker : nullptr, context);
        if (!stream.started) stream.first_split_level = stream.split_level;
      }
      stream.started = true;
      const formats::RecordBatch* fed = &batch;
      if (stream.scheme == Scheme::Split) {
        stream.low_batch.marker = batch.marker;
        stream.low_batch.first_record = batch.first_record;
        stream.low_batch.records.clear();
        for (std::size_t i = 0; i < batch.records.size(); ++i) {
          const Record& record = batch.records[i];
          if (is_other_stream(record.tag)) continue;
          if (!formats::is_level(record.tag)) {
            throw_untagged_record(context, batch.first_record + i + 1, "the split scheme routes");
          }
          if (record.tag >= stream.split_level) stream.low_batch.records.push_back(record);
        }
        fed = &stream.low_batch;
      }
      if (stream.sweep) stream.sweep->feed(*fed);
      if (stream.stack || stream.opt) {
        for (std::size_t i = 0; i < fed->records.size(); ++i) {
          const Record& record = fed->records[i];
          if (is_other_stream(record.tag)) continue;
          feed_stack(stream, record, context.form, context, fed->first_record + i + 1);
        }
      }
    }
  }
  for (Stream& stream : streams) {
    if (stream.sweep) {
      const TraceResult result = stream.sweep->finish();
      for (std::size_t p = 0; p < stream.points.size(); ++p) {
        CurvePoint& point = points[stream.points[p]];
        point.fetches = result.rows[p].fetches;
        point.misses = result.rows[p].misses;
      }
    }
  }
  for (const Stream& stream : streams) {
    if (stream.opt) settle_opt(stream, points);
  }
  for (CurvePoint& point : points) {
    for (const Stream& stream : streams) {
      if (stream.scheme != point.scheme || stream.block != point.block) continue;
      if (stream.scheme == Scheme::Split) point.split_level = stream.first_split_level;
      if (point.assoc == 0 && point.policy == ReplacementPolicy::Lru) {
        point.fetches = stream.full_fetches;
        point.misses = stream.full.misses(
            static_cast<unsigned>(std::countr_zero(point.size / point.block)));
      }
    }
  }
  return points;
}

namespace {

// `full` as in the report: no ways given, or as many as the cache has blocks.
std::string assoc_label(const CurvePoint& point) {
  const bool full = point.assoc == 0 || (point.size / point.block > 1 && point.assoc == point.size / point.block);
  return full ? std::string("full") : std::to_string(point.assoc);
}

}  // namespace

std::optional<std::string> merge_repeated_points(std::vector<CurvePoint>& points) {
  const auto same = [](const CurvePoint& a, const CurvePoint& b) {
    return a.trace == b.trace && a.scheme == b.scheme && a.policy == b.policy && a.block == b.block &&
           a.size == b.size && assoc_label(a) == assoc_label(b);
  };
  std::vector<CurvePoint> distinct;
  for (const CurvePoint& point : points) {
    if (std::none_of(distinct.begin(), distinct.end(), [&](const CurvePoint& kept) { return same(kept, point); })) {
      distinct.push_back(point);
    }
  }
  const std::size_t repeated = points.size() - distinct.size();
  points = std::move(distinct);
  if (repeated == 0) return std::nullopt;
  return fmt::format("--curve: {} point{} repeated an earlier one (a one-set cache of N ways is the fully "
                     "associative one, or a value was listed twice): each cache is printed once",
                     repeated, repeated == 1 ? "" : "s");
}

std::string format_curve(const std::vector<CurvePoint>& points, ReportFormat format) {
  static const std::vector<std::string> columns{"trace", "scheme", "block",   "assoc",  "policy",
                                                "split_level", "size", "fetches", "misses", "miss_ratio"};
  std::vector<std::vector<std::string>> rows;
  rows.reserve(points.size());
  for (const CurvePoint& point : points) {
    const bool split = point.scheme == Scheme::Split;
    rows.push_back({point.trace, split ? "split-low" : "single", std::to_string(point.block),
                    assoc_label(point), std::string(policy_name(point.policy)),
                    split ? std::to_string(point.split_level) : "", std::to_string(point.size),
                    std::to_string(point.fetches), std::to_string(point.misses),
                    miss_ratio_text(point.misses, point.fetches)});
  }
  return format_cells(columns, rows, format,
                      [](std::size_t column) { return column == 0 || column == 1 || column == 4; });
}

}  // namespace nodetrace::cachesim
