// The prefetch columns' checks (config_case_prefetch_checks.hpp).
#include "config_case_prefetch_checks.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace nodetrace::testing {

namespace {

// The blocks a configuration fetched from memory on demand: its misses, a
// retained high cache's loads whether counted as misses or not.
std::uint64_t demand_blocks(const Config& config, const reference::Counts& counts) {
  if (!config.split) return counts.misses;
  return counts.low_misses + (config.retain ? counts.high_loads : counts.high_misses);
}

}  // namespace

// The prefetch columns' counts a row must show (--prefetch): the reference
// with the prefetcher (`with`) and without it (`without`).
std::map<std::string, std::string> expected_prefetch_cells(const Config& config, const reference::Counts& with,
                                                           const reference::Counts& without) {
  return {{"prefetch", prefetch_text(config)},
          {"prefetches", std::to_string(with.prefetches)},
          {"useful_prefetches", std::to_string(with.useful_prefetches)},
          {"misses_without_prefetch", std::to_string(without.misses)}};
}

// The properties of a row's prefetch columns (empty: they hold): accuracy
// useful / prefetches within [0, 1], coverage (without - with) / without at
// most 1 and below 0 only where some prefetch was useless (it evicted a block
// then missed), and bytes per ray (demand blocks + prefetches) x block / rays:
// the traffic is demand misses plus prefetches.
std::string prefetch_properties(const Config& config, const reference::Counts& with,
                                const reference::Counts& without, std::optional<std::uint64_t> rays,
                                const std::map<std::string, std::string>& row) {
  std::string out;
  auto value = [&](const char* column) -> std::optional<double> {
    const auto found = row.find(column);
    if (found == row.end() || found->second.empty()) return std::nullopt;
    return std::stod(found->second);
  };
  // The columns have six decimals, rounded half up: off by at most 5e-7
  // (a tie, such as 3/384, is off by exactly that), plus double's error.
  auto near = [](std::optional<double> got, double want) {
    return got && std::abs(*got - want) <= 5e-7 + 1e-12 * std::max(1.0, std::abs(want));
  };
  const auto accuracy = value("prefetch_accuracy");
  if (with.prefetches == 0) {
    if (accuracy) out += " prefetch_accuracy given without prefetches";
  } else {
    const double want = static_cast<double>(with.useful_prefetches) / static_cast<double>(with.prefetches);
    if (!near(accuracy, want) || *accuracy < 0 || *accuracy > 1) out += fmt::format(" prefetch_accuracy (expected {})", want);
  }
  const auto coverage = value("prefetch_coverage");
  if (without.misses == 0) {
    if (coverage) out += " prefetch_coverage given without misses to cover";
  } else {
    const double want = (static_cast<double>(without.misses) - static_cast<double>(with.misses)) /
                        static_cast<double>(without.misses);
    if (!near(coverage, want) || *coverage > 1 || (*coverage < 0 && with.prefetches == with.useful_prefetches)) {
      out += fmt::format(" prefetch_coverage (expected {}, negative only with useless prefetches)", want);
    }
  }
  const auto per_ray = value("bytes_per_ray");
  if (!rays || *rays == 0) {
    if (per_ray) out += " bytes_per_ray given without rays";
  } else {
    const double want = static_cast<double>((demand_blocks(config, with) + with.prefetches) * config.block) /
                        static_cast<double>(*rays);
    if (!near(per_ray, want)) out += fmt::format(" bytes_per_ray (expected {})", want);
  }
  if (with.useful_prefetches > with.prefetches) out += " more useful prefetches than prefetches";
  return out;
}

}  // namespace nodetrace::testing
