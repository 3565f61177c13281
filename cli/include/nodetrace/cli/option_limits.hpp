// Checks for numeric command-line values, shared by every front end so that
// each value is checked once, where it is parsed, and every tool words the
// error the same way: the option, the value given and the limit.
#pragma once

#include <cstdint>
#include <string_view>

namespace nodetrace::cli {

// Threads a --threads option may ask for: kThreadsPerCore per core, and at
// least kMinThreadLimit whatever the machine (more buys nothing and, by the
// hundred thousand, fails to start).
inline constexpr unsigned kThreadsPerCore = 16;
inline constexpr unsigned kMinThreadLimit = 64;
unsigned thread_limit();

// `requested` (0: one per core) if it is within thread_limit(); otherwise
// throws UsageError naming the option, the value and the limit.
// `unit` names what is counted ("threads", "processes").
unsigned check_thread_count(std::uint64_t requested, std::string_view option,
                            std::string_view unit = "threads");

// `value` if it is a finite number; otherwise throws UsageError naming the
// option and the value.
double check_finite(double value, std::string_view option);

// `value` if it is at most `limit`; otherwise throws UsageError
// "OPTION TEXT: at most LIMIT_TEXT (WHY)".
std::uint64_t check_at_most(std::uint64_t value, std::uint64_t limit, std::string_view option,
                            std::string_view text, std::string_view limit_text, std::string_view why);

}  // namespace nodetrace::cli
