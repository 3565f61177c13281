// dineroIV's command line: the same options, values, defaults and checks, in
// the same order, so the same arguments mean the same simulation.
#include <fmt/format.h>

#include <cctype>
#include <climits>
#include <string>
#include <string_view>

#include "nodetrace/cachesim/dinero/command_line.hpp"
#include "nodetrace/base/byte_size.hpp"
#include "nodetrace/base/error.hpp"

namespace nodetrace::cachesim {

namespace {

using base::UsageError;


[[noreturn]] void usage(const std::string& message) { throw UsageError(message); }

// "-lN-T" prefix: level (1-based) and kind index, and the rest of the option.
struct Prefixed {
  int level = 0;  // 0-based
  int kind = 0;   // 0 u, 1 i, 2 d
  std::string_view rest;
};

std::optional<Prefixed> level_prefix(std::string_view opt) {
  if (opt.size() < 2 || opt[0] != '-' || opt[1] != 'l') return std::nullopt;
  std::size_t i = 2;
  if (i >= opt.size() || !std::isdigit(static_cast<unsigned char>(opt[i]))) return std::nullopt;
  long level = 0;
  while (i < opt.size() && std::isdigit(static_cast<unsigned char>(opt[i]))) {
    level = level * 10 + (opt[i] - '0');
    if (level > 1000) return std::nullopt;
    ++i;
  }
  if (level <= 0 || level > kMaxLevels) return std::nullopt;
  if (i >= opt.size() || opt[i] != '-') return std::nullopt;
  ++i;
  if (i >= opt.size()) return std::nullopt;
  Prefixed p;
  switch (opt[i]) {
    case 'u': p.kind = 0; break;
    case 'i': p.kind = 1; break;
    case 'd': p.kind = 2; break;
    default: return std::nullopt;
  }
  p.level = static_cast<int>(level) - 1;
  p.rest = opt.substr(i + 1);
  return p;
}

// Dinero's argscale_uint: decimal digits, an optional k/m/g (either case)
// suffix; the value is kept in 32 bits as Dinero's unsigned int is.
bool scaled_uint(std::string_view arg, std::uint32_t& value) {
  const std::optional<std::uint64_t> x = base::parse_scaled_number(arg);
  if (!x) return false;
  value = static_cast<std::uint32_t>(*x);
  return true;
}

// Dinero's argscale_uintd (kept as a double there; exact integers here).
bool scaled_count(std::string_view arg, std::uint64_t& value) {
  const std::optional<std::uint64_t> x = base::parse_scaled_number(arg);
  if (!x) return false;
  value = *x;
  return true;
}

bool plain_uint(std::string_view arg, std::uint32_t& value) {
  if (arg.empty()) return false;
  std::uint64_t x = 0;
  for (char c : arg) {
    if (!std::isdigit(static_cast<unsigned char>(c))) return false;
    x = x * 10 + static_cast<std::uint64_t>(c - '0');
    if (x > UINT_MAX) return false;
  }
  value = static_cast<std::uint32_t>(x);
  return true;
}

bool hex_address(std::string_view arg, std::uint64_t& value) {
  if (arg.size() >= 2 && arg[0] == '0' && (arg[1] == 'x' || arg[1] == 'X')) arg.remove_prefix(2);
  if (arg.empty() || arg.size() > 16) return false;
  std::uint64_t x = 0;
  for (char c : arg) {
    if (!std::isxdigit(static_cast<unsigned char>(c))) return false;
    x = x * 16 + static_cast<std::uint64_t>(std::isdigit(static_cast<unsigned char>(c))
                                                ? c - '0'
                                                : std::tolower(static_cast<unsigned char>(c)) - 'a' + 10);
  }
  value = x;
  return true;
}

std::string bad_option(std::string_view opt, std::string_view arg) {
  return fmt::format("bad option: {} {}", opt, arg);
}

// Dinero's verify_options(), in its order.
void verify(DineroOptions& o) {
  for (int lev = 0; lev < o.max_level; ++lev) {
    for (int idu = 0; idu < 3; ++idu) {
      if (o.block_size[idu][lev] != 0 && o.sub_block_size[idu][lev] == 0) {
        o.sub_block_size[idu][lev] = o.block_size[idu][lev];
      }
      if (o.size[idu][lev] != 0) {
        if (o.assoc[idu][lev] == 0) o.assoc[idu][lev] = 1;
        if (o.replacement[idu][lev] == 0) o.replacement[idu][lev] = 'l';
        if (o.fetch[idu][lev] == 0) o.fetch[idu][lev] = 'd';
        if (o.fetch[idu][lev] != 'd' && o.prefetch_distance[idu][lev] == 0) {
          o.prefetch_distance[idu][lev] = 1;
        }
        if (idu != 1 && o.write_allocate[idu][lev] == 0) o.write_allocate[idu][lev] = 'a';
        if (idu != 1 && o.write_back[idu][lev] == 0) o.write_back[idu][lev] = 'a';
      }
    }
  }

  if (o.max_level <= 0) {
    usage("cache size and block size must be specified,\n"
          "e.g.: -l1-isize 16k -l1-dsize 8192 -l1-ibsize 32 -l1-dbsize 16");
  }
  for (int lev = 0; lev < o.max_level; ++lev) {
    int errors = 0;
    int active_caches = 0;
    std::string details;
    for (int idu = 0; idu < 3; ++idu) {
      const int params = (o.block_size[idu][lev] != 0) + (o.sub_block_size[idu][lev] != 0) +
                         (o.size[idu][lev] != 0) + (o.assoc[idu][lev] != 0) +
                         (o.replacement[idu][lev] != 0) + (o.fetch[idu][lev] != 0) +
                         (o.write_allocate[idu][lev] != 0) + (o.write_back[idu][lev] != 0);
      const bool active = params != 0 || o.ccc[idu][lev];
      active_caches += active;
      if (active && params != 6 + 2 * (idu != 1)) {
        if (o.block_size[idu][lev] == 0) {
          details += fmt::format("level {} {}cache block size must be specified, e.g., -l{}-{}bsize 16\n",
                                 lev + 1, cache_kind_letter(idu), lev + 1, cache_kind_letter(idu));
        }
        if (o.size[idu][lev] == 0) {
          details += fmt::format("level {} {}cache size must be specified, e.g., -l{}-{}size 16k\n",
                                 lev + 1, cache_kind_letter(idu), lev + 1, cache_kind_letter(idu));
        }
        ++errors;
      }
    }
    if (active_caches == 0) usage(fmt::format("no level {} cache specified", lev + 1));
    if (errors != 0) usage(fmt::format("{}level {} cache parameters incomplete", details, lev + 1));
  }

  switch (o.informat) {
    case 'd': o.form = formats::RecordForm::Din; break;
    case 'D': o.form = formats::RecordForm::ExtendedDin; break;
    case 'b': o.form = formats::RecordForm::Binary; break;
    default:
      usage(fmt::format("-informat {}: input format not supported (d = din, D = extended din, "
                        "b = binary)",
                        o.informat));
  }

  for (int lev = 0; lev < o.max_level; ++lev) {
    for (int idu = 0; idu < 3; ++idu) {
      const char r = o.replacement[idu][lev];
      if (r != 0 && r != 'l' && r != 'f' && r != 'r') {
        usage(fmt::format("level {} {}cache replacement policy unrecognized", lev + 1, cache_kind_letter(idu)));
      }
    }
  }
  for (int lev = 0; lev < o.max_level; ++lev) {
    for (int idu = 0; idu < 3; ++idu) {
      const char f = o.fetch[idu][lev];
      if (f != 0 && f != 'd' && f != 'a' && f != 'm' && f != 't' && f != 'l' && f != 's') {
        usage(fmt::format("level {} {}cache fetch policy unrecognized", lev + 1, cache_kind_letter(idu)));
      }
      const std::uint32_t block = o.block_size[idu][lev];
      const std::uint32_t sub = o.sub_block_size[idu][lev] != 0 ? o.sub_block_size[idu][lev] : block;
      if ((f == 'l' || f == 's') && sub != 0 && o.prefetch_distance[idu][lev] > block / sub) {
        usage(fmt::format("level {} {}cache prefetch distance > block size", lev + 1, cache_kind_letter(idu)));
      }
      if (f == 'd' && o.prefetch_abort[idu][lev] != 0) {
        usage(fmt::format("level {} {}cache abort % not allowed with demand fetch policy", lev + 1,
                          cache_kind_letter(idu)));
      }
      // Dinero IV holds the percentage in an int: above INT_MAX is negative.
      if (o.prefetch_abort[idu][lev] > 100) {
        usage(fmt::format("level {} {}cache abort % out of range", lev + 1, cache_kind_letter(idu)));
      }
    }
  }
  for (int lev = 0; lev < o.max_level; ++lev) {
    if (o.write_allocate[1][lev] != 0) {
      usage(fmt::format("level {} icache cannot have write allocate policy", lev + 1));
    }
    for (int idu = 0; idu < 3; ++idu) {
      const char w = o.write_allocate[idu][lev];
      if (w != 0 && w != 'a' && w != 'n' && w != 'f') {
        usage(fmt::format("level {} {}cache write allocate policy unrecognized", lev + 1,
                          cache_kind_letter(idu)));
      }
    }
  }
  for (int lev = 0; lev < o.max_level; ++lev) {
    if (o.write_back[1][lev] != 0) {
      usage(fmt::format("level {} icache cannot have write back policy", lev + 1));
    }
    for (int idu = 0; idu < 3; ++idu) {
      const char w = o.write_back[idu][lev];
      if (w != 0 && w != 'a' && w != 'n' && w != 'f') {
        usage(fmt::format("level {} {}cache write back policy unrecognized", lev + 1, cache_kind_letter(idu)));
      }
    }
  }
  for (int lev = 0; lev < o.max_level; ++lev) {
    for (int idu = 0; idu < 3; ++idu) {
      if (o.sub_block_size[idu][lev] > 32768) {
        usage(fmt::format("level {} {}cache sub-block size must be <= 32768", lev + 1, cache_kind_letter(idu)));
      }
    }
  }
  for (int lev = 0; lev < o.max_level; ++lev) {
    for (int idu = 0; idu < 3; ++idu) {
      const std::uint32_t block = o.block_size[idu][lev];
      const std::uint32_t sub = o.sub_block_size[idu][lev];
      if (block != 0 && sub > block) {
        usage(fmt::format("level {} {}cache has sub-blocksize > blocksize", lev + 1, cache_kind_letter(idu)));
      }
      if (sub != 0 && block / sub > 32) {
        usage(fmt::format("level {} {}cache must have no more than 32 sub-blocks per block", lev + 1,
                          cache_kind_letter(idu)));
      }
    }
  }
  if (o.stat_idcombine) {
    for (int lev = 0; lev < o.max_level; ++lev) {
      if (o.block_size[1][lev] != o.block_size[2][lev]) {
        usage(fmt::format("level {} i & d cache block sizes must match for -stat-idcombine", lev + 1));
      }
      if (o.sub_block_size[1][lev] != o.sub_block_size[2][lev]) {
        usage(fmt::format("level {} i & d cache sub-block sizes must match for -stat-idcombine", lev + 1));
      }
    }
  }
  for (int lev = 0; lev < o.max_level; ++lev) {
    auto any = [&](int idu) {
      return o.block_size[idu][lev] != 0 || o.sub_block_size[idu][lev] != 0 || o.size[idu][lev] != 0 ||
             o.assoc[idu][lev] != 0 || o.replacement[idu][lev] != 0 || o.fetch[idu][lev] != 0 ||
             o.write_allocate[idu][lev] != 0 || o.write_back[idu][lev] != 0 || o.ccc[idu][lev];
    };
    if (any(0) && (any(1) || any(2))) {
      usage(fmt::format("level {} has i or d together with u cache parameters", lev + 1));
    }
  }
  for (int lev = 0; lev < o.max_level; ++lev) {
    for (int idu = 0; idu < 3; ++idu) {
      if (o.block_size[idu][lev] != 0 &&
          std::uint64_t{o.block_size[idu][lev]} * o.assoc[idu][lev] > o.size[idu][lev]) {
        usage(fmt::format("level {} {}cache size < blocksize * associativity", lev + 1, cache_kind_letter(idu)));
      }
    }
  }
  for (int lev = 1; lev < o.max_level; ++lev) {
    if (o.block_size[0][lev - 1] != 0 && o.block_size[0][lev] == 0) {
      usage(fmt::format("level {} cache is unified, level {} is not", lev, lev + 1));
    }
  }
}

CacheConfig cache_config(const DineroOptions& o, int idu, int lev) {
  CacheConfig c;
  c.size = o.size[idu][lev];
  c.block_size = o.block_size[idu][lev];
  c.sub_block_size = o.sub_block_size[idu][lev];
  c.assoc = o.assoc[idu][lev];
  switch (o.replacement[idu][lev]) {
    case 'f': c.replacement = ReplacementPolicy::Fifo; break;
    case 'r': c.replacement = ReplacementPolicy::Random; break;
    default: c.replacement = ReplacementPolicy::Lru; break;
  }
  switch (o.write_allocate[idu][lev]) {
    case 'n': c.write_allocate = WriteAllocate::Never; break;
    case 'f': c.write_allocate = WriteAllocate::NoFetch; break;
    default: c.write_allocate = WriteAllocate::Always; break;
  }
  switch (o.write_back[idu][lev]) {
    case 'n': c.write_back = WriteBack::Never; break;
    case 'f': c.write_back = WriteBack::NoFetch; break;
    default: c.write_back = WriteBack::Always; break;
  }
  c.classify_misses = o.ccc[idu][lev];
  switch (o.fetch[idu][lev]) {
    case 'a': c.fetch = FetchPolicy::Always; break;
    case 'm': c.fetch = FetchPolicy::Miss; break;
    case 't': c.fetch = FetchPolicy::Tagged; break;
    case 'l': c.fetch = FetchPolicy::LoadForward; break;
    case 's': c.fetch = FetchPolicy::SubBlock; break;
    default: c.fetch = FetchPolicy::Demand; break;
  }
  c.prefetch_distance = o.prefetch_distance[idu][lev];
  c.prefetch_abort = o.prefetch_abort[idu][lev];
  return c;
}

}  // namespace

DineroOptions parse_dinero_options(const std::vector<std::string>& args) {
  DineroOptions o;
  bool have_trace = false;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& opt = args[i];
    const std::string* next = i + 1 < args.size() ? &args[i + 1] : nullptr;
    // Options that take a value consume the next argument, which may not
    // start with '-' (Dinero's rule).
    auto value = [&]() -> const std::string& {
      if (next == nullptr || (!next->empty() && (*next)[0] == '-')) {
        usage(fmt::format("\"{}\" option requires additional argument", opt));
      }
      ++i;
      return *next;
    };

    if (opt == "-help" || opt == "--help" || opt == "-h") {
      o.request = DineroOptions::Request::Help;
      return o;
    }
    if (opt == "-copyright") {
      o.request = DineroOptions::Request::Copyright;
      return o;
    }
    if (opt == "-contact") {
      o.request = DineroOptions::Request::Contact;
      return o;
    }
    if (opt == "-dineroIII") {
      o.request = DineroOptions::Request::DineroIII;
      return o;
    }
    if (opt == "-custom") usage("-custom: generating a custom simulator is not supported");

    if (const auto p = level_prefix(opt)) {
      // Dinero raises its highest level on any well-formed -lN-T prefix.
      const std::string_view rest = p->rest;
      const int lev = p->level;
      const int idu = p->kind;
      auto note_level = [&] { o.max_level = std::max(o.max_level, lev + 1); };
      if (rest == "size" || rest == "bsize" || rest == "sbsize") {
        note_level();
        const std::string& arg = value();
        std::uint32_t x = 0;
        if (!scaled_uint(arg, x)) usage(bad_option(opt, arg));
        if (x == 0 || (x & (x - 1)) != 0) usage(fmt::format("option {} arg must be power of 2", opt));
        (rest == "size" ? o.size : rest == "bsize" ? o.block_size : o.sub_block_size)[idu][lev] = x;
        continue;
      }
      if (rest == "assoc" || rest == "pfdist" || rest == "pfabort") {
        note_level();
        const std::string& arg = value();
        std::uint32_t x = 0;
        if (!plain_uint(arg, x)) usage(bad_option(opt, arg));
        (rest == "assoc" ? o.assoc : rest == "pfdist" ? o.prefetch_distance : o.prefetch_abort)[idu][lev] = x;
        continue;
      }
      if (rest == "repl" || rest == "fetch" || rest == "walloc" || rest == "wback") {
        note_level();
        const std::string& arg = value();
        if (arg.size() != 1) usage(bad_option(opt, arg));
        (rest == "repl"     ? o.replacement
         : rest == "fetch"  ? o.fetch
         : rest == "walloc" ? o.write_allocate
                            : o.write_back)[idu][lev] = arg[0];
        continue;
      }
      if (rest == "ccc") {
        note_level();
        o.ccc[idu][lev] = true;
        continue;
      }
    }
    if (opt == "-skipcount" || opt == "-flushcount" || opt == "-maxcount" || opt == "-stat-interval") {
      const std::string& arg = value();
      std::uint64_t x = 0;
      if (!scaled_count(arg, x)) usage(bad_option(opt, arg));
      (opt == "-skipcount"    ? o.skip_count
       : opt == "-flushcount" ? o.flush_count
       : opt == "-maxcount"   ? o.max_count
                              : o.stat_interval) = x;
      continue;
    }
    if (opt == "-informat") {
      const std::string& arg = value();
      if (arg.size() != 1) usage(bad_option(opt, arg));
      o.informat = arg[0];
      o.informat_given = true;
      continue;
    }
    if (opt == "-on-trigger" || opt == "-off-trigger") {
      const std::string& arg = value();
      std::uint64_t x = 0;
      if (!hex_address(arg, x)) usage(bad_option(opt, arg));
      (opt == "-on-trigger" ? o.on_trigger : o.off_trigger) = x;
      continue;
    }
    if (opt == "-stat-idcombine") {
      o.stat_idcombine = true;
      continue;
    }
    if (opt == "-" || (!opt.empty() && opt[0] != '-')) {
      if (have_trace) usage(fmt::format("more than one trace file given ('{}', '{}')", o.trace_path, opt));
      o.trace_path = opt;
      have_trace = true;
      continue;
    }
    if (opt.size() >= 2 && opt[0] == '-' && std::string_view("uidbSarfpPwAQzZ").find(opt[1]) != std::string_view::npos &&
        !level_prefix(opt)) {
      usage(fmt::format("\"{}\" option not recognized for Dinero IV;\n"
                        "try \"cachesim dinero -dineroIII\" for Dinero III --> IV option correspondence.",
                        opt));
    }
    usage(fmt::format("\"{}\" option not recognized.", opt));
  }

  verify(o);

  HierarchyConfig& h = o.hierarchy;
  h.levels.resize(static_cast<std::size_t>(o.max_level));
  for (int lev = 0; lev < o.max_level; ++lev) {
    if (o.size[0][lev] != 0) h.levels[lev].unified = cache_config(o, 0, lev);
    if (o.size[1][lev] != 0) h.levels[lev].instruction = cache_config(o, 1, lev);
    if (o.size[2][lev] != 0) h.levels[lev].data = cache_config(o, 2, lev);
  }
  h.skip_count = o.skip_count;
  h.max_count = o.max_count;
  h.flush_count = o.flush_count;
  h.stat_interval = o.stat_interval;
  h.on_trigger = o.on_trigger;
  h.off_trigger = o.off_trigger;
  h.validate();  // geometry Dinero would accept but cannot exist
  return o;
}

}  // namespace nodetrace::cachesim
