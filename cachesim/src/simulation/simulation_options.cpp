#include "nodetrace/cachesim/simulation/simulation_options.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <charconv>

#include "nodetrace/base/byte_size.hpp"
#include "nodetrace/base/error.hpp"
#include "nodetrace/base/output_file.hpp"
#include "nodetrace/cli/distinct_outputs.hpp"
#include "nodetrace/cli/option_limits.hpp"
#include "option_values.hpp"

namespace nodetrace::cachesim {

std::uint64_t cache_size(const std::string& text, const char* option) {
  return cli::check_at_most(base::parse_byte_size(text, option), kMaxCacheBytes, option, text, "256m",
                            "the largest cache: its state is allocated up front");
}

std::uint32_t assoc_option(const std::string& text, const char* option) {
  try {
    return parse_assoc(text);
  } catch (const base::UsageError& error) {
    throw base::UsageError(fmt::format("{}: {}", option, error.what()));
  }
}

namespace {

// Sizes and blocks are powers of two (a cache's sets, ways and blocks are):
// refused naming the option and the value as typed.
void check_power_of_two(std::uint64_t value, const std::string& text, const char* option) {
  if (!std::has_single_bit(value)) {
    throw base::UsageError(fmt::format("{} {}: {} bytes is not a power of two (a cache's size and blocks are)",
                                       option, text, value));
  }
}

template <typename T, typename Parse>
std::vector<T> parse_list(const std::vector<std::string>& texts, const char* option, Parse parse,
                          const char* accepted) {
  std::vector<T> values;
  for (const std::string& text : texts) {
    const auto value = parse(text);
    if (!value) {
      throw base::UsageError(fmt::format("{}: '{}' is not one of {}", option, text, accepted));
    }
    values.push_back(*value);
  }
  return values;
}

}  // namespace

SweepOptions sweep_options(const SimulationOptions& line) {
  if (std::count(line.traces.begin(), line.traces.end(), "-") > 1) {
    throw base::UsageError("traces: standard input (-) is named more than once; it can be read only once");
  }
  SweepOptions options;
  options.sizes.clear();
  for (const auto& text : line.sizes) options.sizes.push_back(cache_size(text, "--size"));
  options.blocks.clear();
  for (const auto& text : line.blocks) {
    const std::uint64_t block = base::parse_byte_size(text, "--block");
    if (block > (1u << 30)) throw base::UsageError(fmt::format("--block {} is too large", text));
    check_power_of_two(block, text, "--block");
    options.blocks.push_back(static_cast<std::uint32_t>(block));
  }
  for (std::size_t i = 0; i < options.sizes.size(); ++i) {
    for (std::size_t b = 0; b < options.blocks.size(); ++b) {
      const std::uint64_t blocks = options.sizes[i] / options.blocks[b];
      if (blocks > kMaxCacheBlocks) {
        throw base::UsageError(fmt::format("--size {} with --block {}: {} blocks, at most {} in one cache "
                                           "(the simulator keeps each block's state)",
                                           line.sizes[i], line.blocks[b], blocks, kMaxCacheBlocks));
      }
    }
  }
  options.assocs.clear();
  for (const auto& text : line.assocs) options.assocs.push_back(assoc_option(text, "--assoc"));
  options.policies =
      parse_list<ReplacementPolicy>(line.policies, "--policy", parse_policy_name, kPolicyNames.data());
  options.schemes = parse_list<Scheme>(line.schemes, "--scheme", parse_scheme_name, "single, split");
  // A single cache is --size, and the split's halves are powers of two only
  // if --size is; with --high-size or --low-size the split's caches are
  // checked as such.
  const bool size_is_a_cache = std::find(options.schemes.begin(), options.schemes.end(), Scheme::Single) !=
                                   options.schemes.end() ||
                               (line.high_size.empty() && line.low_size.empty());
  for (std::size_t i = 0; i < options.sizes.size() && size_is_a_cache; ++i) {
    check_power_of_two(options.sizes[i], line.sizes[i], "--size");
  }
  options.high_policies =
      parse_list<HighPolicy>(line.high_policies, "--high-policy", parse_high_policy_name, "retain, cache");
  options.split_levels.clear();
  for (const auto& text : line.split_levels) {
    if (text == "auto") {
      options.split_levels.push_back(std::nullopt);
      continue;
    }
    std::uint32_t level = 0;
    const auto [next, error] = std::from_chars(text.data(), text.data() + text.size(), level);
    if (error != std::errc{} || next != text.data() + text.size() || level > formats::kMaxLevel) {
      throw base::UsageError(
          fmt::format("--split-level: '{}' is not a level: expected a number or 'auto'", text));
    }
    options.split_levels.push_back(level);
  }
  if (!line.high_size.empty()) options.high_size = cache_size(line.high_size, "--high-size");
  if (!line.low_size.empty()) options.low_size = cache_size(line.low_size, "--low-size");
  if (!line.high_assoc.empty()) options.high_assoc = assoc_option(line.high_assoc, "--high-assoc");
  options.count_loads = line.count_loads;
  // The command line takes only these names (run_arguments.cpp); a caller
  // that fills the struct itself gets the same refusal as a message.
  const std::optional<FetchPolicy> fetch = parse_fetch_policy_name(line.fetch);
  if (!fetch) {
    throw base::UsageError(fmt::format(
        "--fetch: '{}' is not one of demand, always, miss, tagged, load-forward, subblock", line.fetch));
  }
  options.fetch = *fetch;
  options.prefetch_distance = line.prefetch_distance;
  options.per_level = !line.per_level.empty();
  options.per_animation_frame = !line.per_frame.empty();
  if (line.per_level == "-" && line.per_frame == "-") {
    throw base::UsageError(
        "--per-level - and --per-frame -: one table per output; write at least one of them to a file");
  }
  cli::check_distinct_outputs(
      {{"--per-level", line.per_level}, {"--per-frame", line.per_frame}, {"--per-unit", line.per_unit}});
  for (const std::string* file : {&line.per_level, &line.per_frame, &line.per_unit}) {
    if (file->empty() || *file == "-") continue;
    for (const std::string& trace : line.traces) {
      if (trace != "-" && cli::same_output_file(trace, *file)) {
        throw base::UsageError(fmt::format("{}: named both as a trace{} and as a table to write", *file,
                                           trace == *file ? "" : fmt::format(" ('{}')", trace)));
      }
    }
    // Before the simulation, not after it.
    base::check_output_writable(*file);
  }
  return options;
}

std::optional<std::string> split_size_note(const SimulationOptions& line, const SweepOptions& options) {
  if (!options.high_size || !options.low_size || !line.sizes_given ||
      std::find(options.schemes.begin(), options.schemes.end(), Scheme::Split) == options.schemes.end()) {
    return std::nullopt;
  }
  const std::uint64_t total = *options.high_size + *options.low_size;
  if (std::all_of(options.sizes.begin(), options.sizes.end(), [&](std::uint64_t size) { return size == total; })) {
    return std::nullopt;
  }
  std::string sizes;
  for (const std::string& size : line.sizes) sizes += (sizes.empty() ? "" : ",") + size;
  return fmt::format("--size {} sizes the single cache only: the split cache is --high-size {} + --low-size {} "
                     "= {} bytes in all",
                     sizes, line.high_size, line.low_size, total);
}

formats::ReaderOptions reader_options(const SimulationOptions& line) {
  formats::ReaderOptions options;
  options.tags_are_levels = line.tags_are_levels;
  options.threads = cli::check_thread_count(line.threads, "--threads");
  if (!line.informat.empty()) {
    options.form = formats::parse_form_name(line.informat);
    if (!options.form) {
      throw base::UsageError(fmt::format("--informat: '{}' is not one of din, xdin, binary", line.informat));
    }
  }
  // Damage is caught by zstd's frame checksums and the content hash; the
  // record hash (a pass over all the text) is left to `tracetool verify`.
  options.check_record_hash = false;
  return options;
}

}  // namespace nodetrace::cachesim
