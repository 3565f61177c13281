// The memory a run may still take on this machine, for the programs that
// allocate large state up front and check it before they start.
#pragma once

#include <cstdint>
#include <optional>

namespace nodetrace::base {

// The smaller of the system's available memory (Linux: MemAvailable of
// /proc/meminfo) and the process's address-space limit (RLIMIT_AS), in
// bytes; nullopt when neither is known.
std::optional<std::uint64_t> available_memory_bytes();

}  // namespace nodetrace::base
