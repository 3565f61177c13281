// Byte sizes as users write them on command lines: "4096", "4k", "16K", "1m",
// "2g" (binary multiples, as Dinero IV reads them). Shared by every front end
// so that `tracer --high-size 4k` and `cachesim run --size 4k` agree.
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>

namespace nodetrace::base {

// Decimal digits, optionally followed by one of k, m, g (either case, binary
// multiples); zero allowed. nullopt for anything else or above 64 bits.
std::optional<std::uint64_t> parse_scaled_number(std::string_view text);

// A positive byte count, optionally followed by one of k, m, g (either case).
// Throws UsageError saying what was expected for anything else (zero,
// negative, overflow, other suffixes).
std::uint64_t parse_byte_size(std::string_view text);
// The same, the error starting with the option's name ("--size: '3x' is ...").
std::uint64_t parse_byte_size(std::string_view text, std::string_view option);

}  // namespace nodetrace::base
