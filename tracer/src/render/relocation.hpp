// Records of one layout moved to another layout's addresses.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "nodetrace/formats/record/record.hpp"
#include "nodetrace/tracer/accel/layout.hpp"
#include "nodetrace/tracer/accel/traversal.hpp"

namespace nodetrace::tracer {

// The address, in layout `to`, of the node in each slot of layout `from`.
std::vector<std::uint64_t> relocation(const Layout& from, const Layout& to, const AddressMap& addresses);

// `records` with each node fetch (a level tag) moved to its node's address in
// the other layout; the other streams do not depend on the layout.
void relocate(std::span<const formats::Record> records, const std::vector<std::uint64_t>& address_of_slot,
              const AddressMap& addresses, std::vector<formats::Record>& out);

}  // namespace nodetrace::tracer
