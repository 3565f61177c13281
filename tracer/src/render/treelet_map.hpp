// The treelet map a layout's trace carries (FORMAT.md 2.2.2): the address
// range of each treelet of `--layout treelet`.
#pragma once

#include <optional>

#include "nodetrace/formats/container/treelet_map.hpp"
#include "nodetrace/tracer/accel/layout.hpp"
#include "nodetrace/tracer/accel/traversal.hpp"

namespace nodetrace::tracer {

// Treelet layouts only (docs/guide/acceleration-structures.md says why no
// other layout has one): treelet i holds slots treelet_first_slot[i] up to
// the next treelet's first slot (the last one up to the last slot).
std::optional<formats::TreeletMap> treelet_map_of(const Layout& layout, const AddressMap& addresses);

}  // namespace nodetrace::tracer
