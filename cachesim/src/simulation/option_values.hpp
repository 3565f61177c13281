// The option values that several checks read the same way, each refused
// naming its option (base::UsageError).
#pragma once

#include <cstdint>
#include <string>

namespace nodetrace::cachesim {

// A cache's size in bytes, at most kMaxCacheBytes.
std::uint64_t cache_size(const std::string& text, const char* option);

// parse_assoc's value, its message naming `option` (--assoc 0 is a usage
// error of --assoc, not of some associativity).
std::uint32_t assoc_option(const std::string& text, const char* option);

}  // namespace nodetrace::cachesim
