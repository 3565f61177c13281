// The checks of a row's prefetch columns (cachesim run --prefetch) in the
// configuration differential test: the counts against the reference model
// and the properties the columns must keep.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>

#include "config_case_lists.hpp"

namespace nodetrace::testing {

// The prefetch columns' counts a row must show (--prefetch): the reference
// with the prefetcher (`with`) and without it (`without`).
std::map<std::string, std::string> expected_prefetch_cells(const Config& config, const reference::Counts& with,
                                                           const reference::Counts& without);

// The properties of a row's prefetch columns; empty when they hold.
std::string prefetch_properties(const Config& config, const reference::Counts& with,
                                const reference::Counts& without, std::optional<std::uint64_t> rays,
                                const std::map<std::string, std::string>& row);

}  // namespace nodetrace::testing
