#include "render/relocation.hpp"

namespace nodetrace::tracer {

std::vector<std::uint64_t> relocation(const Layout& from, const Layout& to, const AddressMap& addresses) {
  std::vector<std::uint64_t> address_of_slot(from.slot_of_node.size());
  for (std::size_t node = 0; node < from.slot_of_node.size(); ++node) {
    address_of_slot[from.slot_of_node[node]] =
        addresses.node_base + std::uint64_t{to.slot_of_node[node]} * addresses.node_size;
  }
  return address_of_slot;
}

void relocate(std::span<const formats::Record> records, const std::vector<std::uint64_t>& address_of_slot,
              const AddressMap& addresses, std::vector<formats::Record>& out) {
  out.assign(records.begin(), records.end());
  for (formats::Record& record : out) {
    if (!formats::is_level(record.tag)) continue;
    record.address = address_of_slot[(record.address - addresses.node_base) / addresses.node_size];
  }
}

}  // namespace nodetrace::tracer
