// The option lists of one configuration case, before they are expanded,
// and the command-line text of them: shared by the generator
// (config_case_generator.cpp) and the render check (config_case_checks.cpp).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "config_cases.hpp"
#include "seeded_draw.hpp"

namespace nodetrace::testing {

// The reference model's names, as the case files use them.
using reference::Config;
using reference::Fetch;
using reference::Policy;
using reference::TraceRecord;

constexpr std::uint64_t kTop = ~std::uint64_t{0};
constexpr const char* kTypeLetters = "rwimcv";

// The option lists of one case, before they are expanded.
struct Lists {
  std::vector<std::uint64_t> sizes, blocks;
  std::vector<std::uint32_t> assocs;  // 0: full
  std::vector<std::string> policies, schemes, split_levels, high_policies;
  std::optional<std::uint64_t> high_size, low_size;
  std::optional<std::uint32_t> high_assoc;
  bool count_loads = false;
  std::string fetch = "demand";
  std::optional<std::uint32_t> distance;
  bool private_units = false;
  std::optional<reference::L2Config> l2;
  bool l2_defaults = false;  // --l2-block and --l2-assoc left to their defaults (64, 8)
  std::vector<std::string> prefetches;  // --prefetch (empty: not given)
  std::vector<std::string> other;  // --threads, --informat, --tags-are-levels, --units shared
};

// The report's `prefetch` cell of `config`: none, treelet[:B], treelet-low[:B].
std::string prefetch_text(const Config& config);
std::string join(const std::vector<std::string>& values, const char* separator = ",");
std::string assoc_text(std::uint32_t assoc);
// Whether a prefetch from some record may reach 2^32 (Dinero IV's engine keeps 32 bits).
bool reaches_2_32(const std::vector<TraceRecord>& records);
// The lists of case `c`; `invalidations`: the trace holds some.
Lists make_lists(Draw& draw, const ConfigCase& c, const ConfigCaseOptions& options, bool invalidations);
// The arguments of `lists` with the given value lists (a list run, or one configuration alone).
std::vector<std::string> arguments(const Lists& l, const std::vector<std::string>& sizes,
                                   const std::vector<std::string>& blocks, const std::vector<std::string>& assocs,
                                   const std::vector<std::string>& policies, const std::vector<std::string>& schemes,
                                   const std::vector<std::string>& split_levels,
                                   const std::vector<std::string>& high_policies);
std::vector<std::string> texts(const std::vector<std::uint64_t>& values);
std::vector<std::string> assoc_texts(const std::vector<std::uint32_t>& values);

}  // namespace nodetrace::testing
