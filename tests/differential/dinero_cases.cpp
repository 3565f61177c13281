// The generator and the comparison of the differential test (see
// dinero_cases.hpp), from seeded draws (seeded_draw.hpp).
#include "dinero_cases.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <bit>
#include <fstream>
#include <random>

#include "address_stream.hpp"
#include "seeded_draw.hpp"
#include "test_support.hpp"

namespace nodetrace::testing {

namespace {

enum Kind { Unified = 0, Instruction = 1, Data = 2 };
constexpr const char* kKind = "uid";

struct Record {
  std::uint64_t address;
  std::uint32_t size;
  int type;  // 0 read, 1 write, 2 instruction fetch, 3 misc, 4 copy-back, 5 invalidate
};

// Records of address streams (address_stream.hpp) and random types and sizes.
std::vector<Record> make_records(Draw& draw, char informat) {
  std::uint64_t count = 0;
  const auto size_class = draw.below(10);
  if (size_class < 3) {
    count = draw.between(20, 500);
  } else if (size_class < 8) {
    count = draw.between(500, 3000);
  } else {
    count = draw.between(3000, 8000);
  }
  // Binary records hold 32-bit addresses, which Dinero IV sign-extends from
  // bit 31: kept below 2^31, where both read them alike.
  const std::array<std::uint64_t, 5> bases = {0x0, 0x1000, 0x400000, 0x10000000, 0x7ff00000};
  const bool wide = informat == 'D' && draw.chance(20);
  std::vector<Record> records;
  records.reserve(count);
  AddressStream stream(StreamShape{}, [&](Draw& d) {
    std::uint64_t base = d.pick(bases) + d.below(1 << 16);
    if (wide) base += std::uint64_t{0x7ffe} << 32;
    return base;
  });
  while (records.size() < count) {
    const std::uint64_t address = stream.next(draw);
    Record r;
    const auto t = draw.below(200);
    r.type = t < 90 ? 0 : t < 140 ? 1 : t < 180 ? 2 : t < 194 ? 3 : t < 197 ? 4 : 5;
    const auto s = draw.below(10);
    r.size = s < 3 ? 4 : s < 5 ? 8 : static_cast<std::uint32_t>(draw.between(1, 64));
    r.address = address;
    if (informat == 'b') {
      r.address &= 0x7FFFFFFFu;
      if (r.address + r.size > 0x80000000u) r.address = 0x7FFFFF00u;
    }
    records.push_back(r);
  }
  return records;
}

std::string trace_bytes(const std::vector<Record>& records, char informat) {
  std::string out;
  constexpr const char* kLetter = "rwimcv";
  for (const Record& r : records) {
    if (informat == 'd') {
      out += fmt::format("{:x} {:x}\n", r.type, r.address);
    } else if (informat == 'D') {
      out += fmt::format("{} {:x} {:x}\n", kLetter[r.type], r.address, r.size);
    } else {
      const auto a = static_cast<std::uint32_t>(r.address);
      const char bytes[8] = {static_cast<char>(a), static_cast<char>(a >> 8), static_cast<char>(a >> 16),
                             static_cast<char>(a >> 24), static_cast<char>(r.size),
                             static_cast<char>(r.size >> 8), static_cast<char>(r.type), 0};
      out.append(bytes, 8);
    }
  }
  return out;
}

std::string byte_count(Draw& draw, std::uint64_t bytes) {
  // Dinero IV's suffixes, sometimes.
  if (bytes >= 1024 && bytes % 1024 == 0 && draw.chance(50)) return fmt::format("{}k", bytes / 1024);
  return fmt::format("{}", bytes);
}

struct CacheShape {
  std::uint32_t block = 0, sub_block = 0;
};

void add_cache(Draw& draw, std::vector<std::string>& args, int level, int kind, CacheShape shape) {
  const std::string p = fmt::format("-l{}-{}", level, kKind[kind]);
  auto option = [&](const std::string& name, const std::string& value) {
    args.push_back(p + name);
    args.push_back(value);
  };
  const std::uint64_t sets = std::uint64_t{1} << draw.below(7);
  std::uint64_t assoc = std::uint64_t{1} << draw.below(4);
  const std::uint64_t size = shape.block * sets * assoc;
  if (draw.chance(15)) assoc = size / shape.block;  // fully associative
  option("size", byte_count(draw, size));
  option("bsize", byte_count(draw, shape.block));
  if (shape.sub_block != shape.block || draw.chance(20)) option("sbsize", byte_count(draw, shape.sub_block));
  if (assoc != 1 || draw.chance(30)) option("assoc", fmt::format("{}", assoc));
  const auto r = draw.below(20);
  if (r < 16 || draw.chance(50)) option("repl", r < 9 ? "l" : r < 15 ? "f" : "r");
  const std::array<const char*, 6> fetches = {"d", "a", "m", "t", "l", "s"};
  const char* fetch = draw.chance(40) ? "d" : fetches[draw.between(1, 5)];
  if (fetch[0] != 'd' || draw.chance(30)) option("fetch", fetch);
  if (fetch[0] != 'd') {
    const std::uint64_t per_block = shape.block / shape.sub_block;
    const bool in_block = fetch[0] == 'l' || fetch[0] == 's';
    if (draw.chance(50)) option("pfdist", fmt::format("{}", in_block ? draw.between(1, per_block) : draw.between(1, 6)));
    if (draw.chance(30)) option("pfabort", fmt::format("{}", draw.below(101)));
  }
  if (kind != Instruction) {
    const std::array<const char*, 3> policies = {"a", "n", "f"};
    if (draw.chance(70)) option("walloc", draw.pick(policies));
    if (draw.chance(70)) option("wback", draw.pick(policies));
  }
  if (draw.chance(20)) args.push_back(p + "ccc");
}

CacheShape make_shape(Draw& draw) {
  CacheShape shape;
  shape.block = std::uint32_t{4} << draw.below(6);  // 4..128
  // At most 16 sub-blocks per block. With 32, a reference covering a whole
  // block gets Dinero IV's 32-bit mask 0 (cachesim reproduces that), which
  // leaves invalid blocks among the valid ones and, in sets of more than 8
  // blocks, corrupts its hash chains: it crashes, loops, or counts what its
  // memory layout decides. Such configurations are left out, not compared.
  const auto most = std::min<std::uint64_t>(4, static_cast<std::uint64_t>(std::countr_zero(shape.block)));
  shape.sub_block = draw.chance(60) ? shape.block : shape.block >> draw.between(1, most);
  return shape;
}

}  // namespace

DineroCase make_dinero_case(std::uint64_t seed) {
  Draw draw(seed);
  DineroCase c;
  c.seed = seed;
  const auto f = draw.below(10);
  const char informat = f < 3 ? 'd' : f < 8 ? 'D' : 'b';
  const std::vector<Record> records = make_records(draw, informat);
  c.trace = trace_bytes(records, informat);
  c.trace_name = informat == 'd' ? "trace.din" : informat == 'D' ? "trace.xdin" : "trace.bin";

  std::vector<std::string>& args = c.args;
  args = {"-informat", std::string(1, informat)};
  const int levels = static_cast<int>(draw.chance(30) ? 1 : draw.between(1, 5));
  const bool idcombine = draw.chance(15);
  bool unified = draw.chance(40);
  for (int level = 1; level <= levels; ++level) {
    if (!unified && level > 1 && draw.chance(40)) unified = true;  // unified from here on
    if (unified) {
      add_cache(draw, args, level, Unified, make_shape(draw));
      continue;
    }
    const CacheShape i_shape = make_shape(draw);
    const CacheShape d_shape = idcombine || draw.chance(30) ? i_shape : make_shape(draw);
    // A level of only one side is allowed, except with -stat-idcombine.
    const auto sides = idcombine ? 0 : draw.below(10);
    if (sides != 1) add_cache(draw, args, level, Instruction, i_shape);
    if (sides != 2) add_cache(draw, args, level, Data, d_shape);
  }
  const std::uint64_t n = records.size();
  if (draw.chance(10)) args.insert(args.end(), {"-skipcount", fmt::format("{}", draw.between(1, n / 2 + 1))});
  if (draw.chance(15)) args.insert(args.end(), {"-flushcount", fmt::format("{}", draw.between(5, n / 3 + 5))});
  if (draw.chance(10)) args.insert(args.end(), {"-maxcount", fmt::format("{}", draw.between(1, n + 10))});
  if (draw.chance(10)) args.insert(args.end(), {"-stat-interval", fmt::format("{}", draw.between(n / 5 + 1, n))});
  auto trigger = [&]() {
    // An address from the trace as Dinero IV reads it (din: rounded to 4).
    std::uint64_t a = records[draw.below(n)].address;
    if (informat == 'd') a &= ~std::uint64_t{3};
    return fmt::format("0x{:x}", a);
  };
  if (draw.chance(6)) args.insert(args.end(), {"-on-trigger", trigger()});
  if (draw.chance(6)) args.insert(args.end(), {"-off-trigger", trigger()});
  if (idcombine) args.push_back("-stat-idcombine");
  return c;
}

std::string joined_arguments(const std::vector<std::string>& args) {
  std::string line;
  for (const auto& a : args) {
    if (!line.empty()) line += ' ';
    line += a;  // no argument holds a blank or a shell character
  }
  return line;
}

namespace {

// Warnings without the program name that begins them, and without the notes
// that only cachesim dinero prints (addresses wrapped at 2^32).
std::string warnings_of(const std::string& err) {
  std::string out;
  std::size_t from = 0;
  while (from < err.size()) {
    auto end = err.find('\n', from);
    if (end == std::string::npos) end = err.size();
    std::string line = err.substr(from, end - from);
    from = end + 1;
    if (line.starts_with("cachesim dinero note: ")) continue;
    const auto at = line.find("warning: ");
    out += (at == std::string::npos ? line : line.substr(at)) + "\n";
  }
  return out;
}

}  // namespace

DineroComparison compare_dinero_case(const DineroCase& c, const std::filesystem::path& dinero,
                                     const std::filesystem::path& cachesim,
                                     const std::filesystem::path& work) {
  const auto trace = work / c.trace_name;
  write_file(trace, c.trace);
  const std::string args = joined_arguments(c.args);
  // Every case takes Dinero IV well under a second, unless it loops forever.
  const auto real = run_command("timeout 5 " + shell_quoted(dinero) + " " + args + " < " + shell_quoted(trace));
  const auto ours = run_command(shell_quoted(cachesim) + " dinero " + args + " < " + shell_quoted(trace));
  DineroComparison result;
  result.dinero_status = real.exit_code;
  result.cachesim_status = ours.exit_code;
  result.dinero_out = real.out;
  result.dinero_err = real.err;
  result.cachesim_out = ours.out;
  result.cachesim_err = ours.err;
  result.valid = real.exit_code == 0;
  result.dinero_broke = real.exit_code == 124 || real.exit_code >= 128;
  if (result.dinero_broke) {
    result.same = true;
  } else if (result.valid) {
    result.same = ours.exit_code == 0 && ours.out == real.out && warnings_of(ours.err) == warnings_of(real.err);
  } else {
    result.same = ours.exit_code != 0;
  }
  return result;
}

void keep_dinero_case(const DineroCase& c, const DineroComparison& result,
                      const std::filesystem::path& folder) {
  std::filesystem::create_directories(folder);
  write_file(folder / c.trace_name, c.trace);
  write_file(folder / "args", joined_arguments(c.args) + "\n");
  write_file(folder / "dinero.out", result.dinero_out);
  write_file(folder / "dinero.err", result.dinero_err);
  write_file(folder / "cachesim.out", result.cachesim_out);
  write_file(folder / "cachesim.err", result.cachesim_err);
  write_file(folder / "status", fmt::format("seed {}\ndineroIV exit {}\ncachesim dinero exit {}\n", c.seed,
                                             result.dinero_status, result.cachesim_status));
}

}  // namespace nodetrace::testing
