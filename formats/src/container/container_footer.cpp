#include "container/container_footer.hpp"

#include <fmt/format.h>

#include "container/container.hpp"
#include "nodetrace/base/error.hpp"

namespace nodetrace::formats::detail {

bool footer_leads_to_trailer(const Input& input, std::string_view footer, std::uint64_t size) {
  if (load_le32(footer.data() + 16) != kFooterMagic || load_le32(footer.data() + 12) != kContainerVersion) {
    return false;
  }
  const std::uint64_t json_size = load_le32(footer.data() + 8);
  if (!input.seekable()) return true;
  if (json_size + kFooterSize + kSkippableHeaderSize > size) return false;
  const std::string frame = input.read_at(size - kFooterSize - json_size - kSkippableHeaderSize, kSkippableHeaderSize);
  return load_le32(frame.data()) == kTrailerMagic && load_le32(frame.data() + 4) == json_size + kFooterSize;
}

bool ends_with_container_footer(const Input& input) {
  const std::uint64_t size = input.size();
  if (size < kSkippableHeaderSize + kFooterSize) return false;
  return footer_leads_to_trailer(input, input.read_at(size - kFooterSize, kFooterSize), size);
}

void fail_damaged_header_magic(const std::string& name, const std::string& first_bytes, const char* what) {
  std::string expected;
  append_le32(expected, kHeaderMagic);
  std::size_t byte = 0;
  while (byte + 1 < expected.size() && first_bytes[byte] == expected[byte]) ++byte;
  throw base::FormatError(fmt::format("{}: damaged container: byte {} is {:#04x} where the header magic 50 2A 4D 18 has "
                                "{:#04x} ({} ends with a container trailer)",
                                name, byte, static_cast<unsigned char>(first_bytes[byte]),
                                static_cast<unsigned char>(expected[byte]), what));
}

}  // namespace nodetrace::formats::detail
