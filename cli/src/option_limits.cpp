#include "nodetrace/cli/option_limits.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <thread>

#include "nodetrace/base/error.hpp"

namespace nodetrace::cli {

unsigned thread_limit() {
  const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
  return std::max(kMinThreadLimit, kThreadsPerCore * cores);
}

unsigned check_thread_count(std::uint64_t requested, std::string_view option, std::string_view unit) {
  const unsigned limit = thread_limit();
  if (requested > limit) {
    throw base::UsageError(fmt::format("{} {}: at most {} {} ({} per core, at least {})", option, requested, limit,
                                 unit, kThreadsPerCore, kMinThreadLimit));
  }
  return static_cast<unsigned>(requested);
}

double check_finite(double value, std::string_view option) {
  if (!std::isfinite(value)) {
    throw base::UsageError(fmt::format("{} {}: expected a finite number", option, value));
  }
  return value;
}

std::uint64_t check_at_most(std::uint64_t value, std::uint64_t limit, std::string_view option,
                            std::string_view text, std::string_view limit_text, std::string_view why) {
  if (value > limit) throw base::UsageError(fmt::format("{} {}: at most {} ({})", option, text, limit_text, why));
  return value;
}

}  // namespace nodetrace::cli
