// dineroIV's output: banner, option summary, per-cache metrics tables (same
// labels, tabs and printf number formats), and its main loop around them.
#include <fmt/format.h>

#include <algorithm>
#include <cstdarg>
#include <cstdio>
#include <ostream>
#include <span>
#include <string>

#include "nodetrace/base/error.hpp"
#include "nodetrace/cachesim/dinero/address_width.hpp"
#include "nodetrace/cachesim/dinero/command_line.hpp"

namespace nodetrace::cachesim {

namespace {


void append(std::string& out, const char* format, ...) __attribute__((format(printf, 2, 3)));
void append(std::string& out, const char* format, ...) {
  char buffer[512];
  va_list args;
  va_start(args, format);
  const int n = std::vsnprintf(buffer, sizeof buffer, format, args);
  va_end(args);
  if (n > 0) out.append(buffer, static_cast<std::size_t>(std::min<int>(n, sizeof buffer - 1)));
}

double nonzero(double x) { return x == 0.0 ? 1.0 : x; }

// The counters of one printed table: one cache, or Dinero's bogus combined
// "I/D" cache for -stat-idcombine.
struct Printed {
  std::string name;
  Stats stats;
  bool ccc = false;
  bool sub_blocked = false;
  bool prefetching = false;  // Dinero prints the prefetch rows
};

using PerType = Stats::PerType;
constexpr int kRead = 0, kWrite = 1, kInstr = 2, kMisc = 3;

double d(std::uint64_t x) { return static_cast<double>(x); }

void count_row(std::string& out, const char* label, const PerType& v) {
  append(out, "%s%12.0f\t%12.0f\t%12.0f\t%12.0f\t%12.0f\t%12.0f\n", label, d(Stats::total(v)), d(v[kInstr]),
         d(Stats::data(v)), d(v[kRead]), d(v[kWrite]), d(v[kMisc]));
}

PerType sum(const PerType& a, const PerType& b) {
  PerType total{};
  for (std::size_t i = 0; i < total.size(); ++i) total[i] = a[i] + b[i];
  return total;
}

// A row of every column divided by the Total column of `of`.
void fraction_row(std::string& out, const char* label, const PerType& v, const PerType& of) {
  const double total = nonzero(d(Stats::total(of)));
  append(out, "%s%12.4f\t%12.4f\t%12.4f\t%12.4f\t%12.4f\t%12.4f\n", label, d(Stats::total(v)) / total,
         d(v[kInstr]) / total, d(Stats::data(v)) / total, d(v[kRead]) / total, d(v[kWrite]) / total,
         d(v[kMisc]) / total);
}

// A row of ratios numerator / denominator per column.
void ratio_row(std::string& out, const char* label, const PerType& num, const PerType& den) {
  append(out, "%s%12.4f\t%12.4f\t%12.4f\t%12.4f\t%12.4f\t%12.4f\n", label,
         d(Stats::total(num)) / nonzero(d(Stats::total(den))), d(num[kInstr]) / nonzero(d(den[kInstr])),
         d(Stats::data(num)) / nonzero(d(Stats::data(den))), d(num[kRead]) / nonzero(d(den[kRead])),
         d(num[kWrite]) / nonzero(d(den[kWrite])), d(num[kMisc]) / nonzero(d(den[kMisc])));
}

void cache_table(std::string& out, const Printed& c) {
  const Stats& s = c.stats;
  append(out, "%s\n", c.name.c_str());
  out += " Metrics\t\t      Total\t      Instrn\t       Data\t       Read\t      Write\t       Misc\n";
  out += " -----------------\t      ------\t      ------\t      ------\t      ------\t      ------\t      ------\n";
  const FetchCounts& pf = s.prefetch;
  count_row(out, " Demand Fetches\t\t", s.fetches);
  fraction_row(out, "  Fraction of total\t", s.fetches, s.fetches);
  if (c.prefetching) {
    count_row(out, " Prefetch Fetches\t", pf.fetches);
    fraction_row(out, "  Fraction\t\t", pf.fetches, pf.fetches);
    const PerType all = sum(s.fetches, pf.fetches);
    count_row(out, " Total Fetches\t\t", all);
    fraction_row(out, "  Fraction\t\t", all, all);
  }
  out += "\n";

  count_row(out, " Demand Misses\t\t", s.misses);
  ratio_row(out, "  Demand miss rate\t", s.misses, s.fetches);
  if (c.ccc) {
    count_row(out, "   Compulsory misses\t", s.compulsory);
    count_row(out, "   Capacity misses\t", s.capacity);
    count_row(out, "   Conflict misses\t", s.conflict);
    ratio_row(out, "   Compulsory fraction\t", s.compulsory, s.misses);
    ratio_row(out, "   Capacity fraction\t", s.capacity, s.misses);
    ratio_row(out, "   Conflict fraction\t", s.conflict, s.misses);
  }
  if (c.prefetching) {
    count_row(out, " Prefetch Misses\t", pf.misses);
    ratio_row(out, "  PF miss rate\t\t", pf.misses, pf.fetches);
    if (c.ccc) {
      count_row(out, "   PF compulsory misses\t", pf.compulsory);
      count_row(out, "   PF capacity misses\t", pf.capacity);
      count_row(out, "   PF conflict misses\t", pf.conflict);
      ratio_row(out, "   PF compulsory fract\t", pf.compulsory, pf.misses);
      ratio_row(out, "   PF capacity fract\t", pf.capacity, pf.misses);
      ratio_row(out, "   PF conflict fract\t", pf.conflict, pf.misses);
    }
    count_row(out, " Total Misses\t\t", sum(s.misses, pf.misses));
    ratio_row(out, "  Total miss rate\t", sum(s.misses, pf.misses), sum(s.fetches, pf.fetches));
  }
  out += "\n";

  if (c.sub_blocked) {
    count_row(out, " Demand Block Misses\t", s.block_misses);
    ratio_row(out, "  DB miss rate\t\t", s.block_misses, s.fetches);
    if (c.ccc) {
      count_row(out, "   DB compulsory misses\t", s.compulsory_block);
      count_row(out, "   DB capacity misses\t", s.capacity_block);
      count_row(out, "   DB conflict misses\t", s.conflict_block);
      // Dinero's misplaced parenthesis prints the Misc column's count itself
      // rather than its fraction; reproduced.
      const PerType& num = s.compulsory_block;
      const PerType& den = s.block_misses;
      append(out, "   DB compulsory fract\t%12.4f\t%12.4f\t%12.4f\t%12.4f\t%12.4f\t%12.4f\n",
             d(Stats::total(num)) / nonzero(d(Stats::total(den))), d(num[kInstr]) / nonzero(d(den[kInstr])),
             d(Stats::data(num)) / nonzero(d(Stats::data(den))), d(num[kRead]) / nonzero(d(den[kRead])),
             d(num[kWrite]) / nonzero(d(den[kWrite])), d(num[kMisc]));
      ratio_row(out, "   DB capacity fract\t", s.capacity_block, s.block_misses);
      ratio_row(out, "   DB conflict fract\t", s.conflict_block, s.block_misses);
    }
    if (c.prefetching) {
      count_row(out, " Prefetch Block Misses\t", pf.block_misses);
      ratio_row(out, "  PFB miss rate\t\t", pf.block_misses, pf.fetches);
      if (c.ccc) {
        count_row(out, "   PFB comp misses\t", pf.compulsory_block);
        count_row(out, "   PFB cap misses\t", pf.capacity_block);
        count_row(out, "   PFB conf misses\t", pf.conflict_block);
        ratio_row(out, "   PFB comp fract\t", pf.compulsory_block, pf.block_misses);
        ratio_row(out, "   PFB cap fract\t", pf.capacity_block, pf.block_misses);
        ratio_row(out, "   PFB conf fract\t", pf.conflict_block, pf.block_misses);
      }
      count_row(out, " Total Block Misses\t", sum(s.block_misses, pf.block_misses));
      ratio_row(out, "  Tot blk miss rate\t", sum(s.block_misses, pf.block_misses), sum(s.fetches, pf.fetches));
    }
    out += "\n";
  }

  const double fetches = nonzero(d(s.demand_fetches()));
  append(out, " Multi-block refs      %12.0f\n", d(s.multi_block_refs));
  append(out, " Bytes From Memory\t%12.0f\n", d(s.bytes_from_memory));
  append(out, " ( / Demand Fetches)\t%12.4f\n", d(s.bytes_from_memory) / fetches);
  append(out, " Bytes To Memory\t%12.0f\n", d(s.bytes_to_memory));
  append(out, " ( / Demand Writes)\t%12.4f\n", d(s.bytes_to_memory) / nonzero(d(s.fetches[kWrite])));
  append(out, " Total Bytes r/w Mem\t%12.0f\n", d(s.bytes_from_memory + s.bytes_to_memory));
  append(out, " ( / Demand Fetches)\t%12.4f\n", d(s.bytes_from_memory + s.bytes_to_memory) / fetches);
  out += "\n";
}

Printed printed_cache(const Hierarchy& h, int level, CacheKind kind) {
  const CacheConfig& config = h.cache_config(level, kind);
  Printed p;
  p.name = fmt::format("l{}-{}cache", level, cache_kind_letter(static_cast<int>(kind)));
  p.stats = h.stats(level, kind);
  p.ccc = config.classify_misses;
  p.sub_blocked = config.effective_sub_block_size() != config.block_size;
  p.prefetching = config.fetch != FetchPolicy::Demand;
  return p;
}

}  // namespace

std::string dinero_preamble(const DineroOptions& o) {
  std::string out;
  out += "---Dinero IV cache simulator, version 7\n";
  out += "---Written by Jan Edler and Mark D. Hill\n";
  out += "---Copyright (C) 1997 NEC Research Institute, Inc. and Mark D. Hill.\n";
  out += "---All rights reserved.\n";
  out += "---Copyright (C) 1985, 1989 Mark D. Hill.  All rights reserved.\n";
  out += "---See -copyright option for details\n";
  out += "\n---Summary of options (-help option gives usage information).\n\n";

  // Each -lN-T option in Dinero's table order, then by u, i, d, then level.
  // Dinero's loop runs one level past the last (lev <= maxlevel): that level
  // is unset below 5 levels; with 5 it reads past each row of its [3][5]
  // table into the next kind's level 1, and past the d row out of the table:
  // there d4-7 as built finds the level count after the block sizes and
  // zeros after the others, and prints "-l6-d..." lines accordingly.
  auto value = [&](const auto& values, int idu, int lev, std::uint32_t past_table) -> std::uint32_t {
    if (lev < kMaxLevels) return static_cast<std::uint32_t>(values[idu][lev]);
    return idu < 2 ? static_cast<std::uint32_t>(values[idu + 1][0]) : past_table;
  };
  auto numbers = [&](const char* name, const auto& values, std::uint32_t past_table = 0) {
    for (int idu = 0; idu < 3; ++idu) {
      for (int lev = 0; lev <= o.max_level; ++lev) {
        const std::uint32_t v = value(values, idu, lev, past_table);
        if (v != 0) append(out, "-l%d-%c%s %u\n", lev + 1, cache_kind_letter(idu), name, v);
      }
    }
  };
  auto letters = [&](const char* name, const auto& values) {
    for (int idu = 0; idu < 3; ++idu) {
      for (int lev = 0; lev <= o.max_level; ++lev) {
        const auto v = static_cast<char>(value(values, idu, lev, 0));
        if (v != 0) append(out, "-l%d-%c%s %c\n", lev + 1, cache_kind_letter(idu), name, v);
      }
    }
  };
  numbers("size", o.size);
  numbers("bsize", o.block_size, static_cast<std::uint32_t>(o.max_level));
  numbers("sbsize", o.sub_block_size);
  numbers("assoc", o.assoc);
  letters("repl", o.replacement);
  letters("fetch", o.fetch);
  numbers("pfdist", o.prefetch_distance);
  numbers("pfabort", o.prefetch_abort);
  letters("walloc", o.write_allocate);
  letters("wback", o.write_back);
  for (int idu = 0; idu < 3; ++idu) {
    for (int lev = 0; lev <= o.max_level; ++lev) {
      if (value(o.ccc, idu, lev, 0) != 0) append(out, "-l%d-%cccc\n", lev + 1, cache_kind_letter(idu));
    }
  }
  append(out, "-skipcount %.0f\n", d(o.skip_count));
  append(out, "-flushcount %.0f\n", d(o.flush_count));
  append(out, "-maxcount %.0f\n", d(o.max_count));
  append(out, "-stat-interval %.0f\n", d(o.stat_interval));
  append(out, "-informat %c\n", o.informat);
  append(out, "-on-trigger 0x%llx\n", static_cast<unsigned long long>(o.on_trigger));
  append(out, "-off-trigger 0x%llx\n", static_cast<unsigned long long>(o.off_trigger));
  if (o.stat_idcombine) out += "-stat-idcombine\n";
  return out;
}

std::string dinero_statistics(const Hierarchy& h, const DineroOptions& o) {
  std::string out;
  for (int level = 1; level <= h.level_count(); ++level) {
    if (o.stat_idcombine && !h.has_cache(level, CacheKind::Unified)) {
      Printed combined = printed_cache(h, level, CacheKind::Instruction);
      const Printed data = printed_cache(h, level, CacheKind::Data);
      combined.name = fmt::format("l{}-I/Dcaches", level);
      combined.stats += data.stats;
      combined.ccc = combined.ccc || data.ccc;
      combined.prefetching = combined.prefetching || data.prefetching;
      cache_table(out, combined);
      continue;
    }
    for (CacheKind kind : {CacheKind::Unified, CacheKind::Instruction, CacheKind::Data}) {
      if (h.has_cache(level, kind)) cache_table(out, printed_cache(h, level, kind));
    }
  }
  return out;
}

void run_dinero(const DineroOptions& options, formats::TraceReader& reader, std::ostream& out,
                std::ostream& warnings) {
  HierarchyConfig config = options.hierarchy;
  config.on_stat_interval = [&](const Hierarchy& h) { out << dinero_statistics(h, options); };
  Hierarchy hierarchy(config);

  out << dinero_preamble(options);
  out << "\n---Simulation begins.\n";
  formats::RecordBatch batch;
  bool stopped = false;
  // A container's header names its record form, which decides din's rounding.
  const formats::RecordForm form = reader.form();
  std::uint64_t beyond_32_bits = 0;
  try {
    while (!stopped && reader.next(batch)) {
      const std::size_t consumed = hierarchy.access_batch(batch.records, form);
      beyond_32_bits += records_beyond_32_bits(std::span(batch.records).first(consumed), form);
      stopped = consumed < batch.records.size();
    }
  } catch (const base::FormatError& error) {
    throw base::FormatError(with_informat_hint(options, error.what()));
  }
  if (hierarchy.max_count_exceeded()) {
    out << "---Maximum address count exceeded.\n";
  } else {
    if (hierarchy.references_skipped() < options.skip_count) {
      warnings << "cachesim dinero warning: input ended before -skipcount satisfied\n";
    } else if ((options.on_trigger != 0 || options.off_trigger != 0) && !hierarchy.trigger_toggled()) {
      warnings << "cachesim dinero warning: trace discard trigger addresses were not matched\n";
    } else if (!hierarchy.discarding() && options.off_trigger != 0) {
      warnings << "cachesim dinero warning: tail end of trace not discarded\n";
    }
  }
  if (beyond_32_bits > 0) {
    warnings << "cachesim dinero note: " << beyond_32_bits_note(reader.source_name(), beyond_32_bits) << "\n";
  }
  hierarchy.finish();
  out << "---Simulation complete.\n";
  out << dinero_statistics(hierarchy, options);
  out << "---Execution complete.\n";
}

std::string dinero_help() {
  return R"(Usage: cachesim dinero [Dinero IV options] [TRACE]

A drop-in replacement for dineroIV (Dinero IV, d4-7): takes dineroIV's own
options and prints its output layout, number for number.
The trace is read from TRACE, or from standard input when TRACE is absent or
"-"; plain or zstd-compressed text, and nodetrace containers, are detected.

Options (N = cache level 1..5, T = u unified, i instruction, d data):
 -lN-Tsize P      Size (k, m, g suffixes; power of 2)
 -lN-Tbsize P     Block size
 -lN-Tsbsize P    Sub-block size (default: block size)
 -lN-Tassoc U     Associativity (default 1)
 -lN-Trepl C      Replacement policy: l=LRU, f=FIFO, r=random (default l;
                  random draws the sequence Dinero IV draws from glibc)
 -lN-Tfetch C     Fetch policy: d=demand only, a=always prefetch, m=miss
                  prefetch, t=tagged prefetch, l=load forward, s=subblock
                  (default d)
 -lN-Tpfdist U    Prefetch distance in sub-blocks (default 1)
 -lN-Tpfabort U   Prefetch abort percentage, 0-100 (default 0)
 -lN-Twalloc C    Write allocate: a=always, n=never, f=nofetch (default a)
 -lN-Twback C     Write back: a=always, n=never (write through), f=nofetch
 -lN-Tccc         Compulsory/capacity/conflict miss statistics
 -skipcount U     Skip initial U references
 -flushcount U    Flush caches every U references
 -maxcount U      Stop simulation after U references
 -stat-interval U Show statistics after every U references
 -informat C      Input trace format: d=din, D=extended din, b=binary (default D)
 -on-trigger A    Trigger address (hex) to start simulation
 -off-trigger A   Trigger address (hex) to stop simulation
 -stat-idcombine  Combine I&D cache stats
 -help, --help, -h
                  This message
 -copyright       Who wrote Dinero IV, and that this contains none of its code
 -contact         The same
 -dineroIII       Dinero III options and their Dinero IV replacements

Exit status: 0 success, 1 bad trace data (the record is named), 2 bad usage
(the option is named; -custom and input formats other than d, D and b are
not supported; dineroIV itself exits 1 for bad usage, nodetrace's commands 2).
A din label above 5 is an error (exit 1) where Dinero IV would accept it
silently; the message says what Dinero IV would do with it.
)";
}

}  // namespace nodetrace::cachesim
