// TraceReader::open: which kind of input a trace is (FORMAT.md section 3),
// from its first 4 bytes and, for a file, its last 20; reader_kinds.hpp has
// a reader for each.
#include "nodetrace/formats/read/trace_reader.hpp"

#include <fmt/format.h>

#include "nodetrace/base/error.hpp"
#include "container/container.hpp"
#include "container/container_footer.hpp"
#include "read/reader_kinds.hpp"
#include "read/records_required.hpp"

namespace nodetrace::formats {

TraceReader::~TraceReader() = default;

namespace {

std::unique_ptr<TraceReader> open_input(const std::string& path, const ReaderOptions& given_options) {
  // Binary records cannot be told from text by their bytes for sure, but a
  // name says so as the writers choose it (tracer -o t.bin).
  ReaderOptions options = given_options;
  if (!options.form && form_of_file_name(path) == RecordForm::Binary) options.form = RecordForm::Binary;
  detail::OpenedInput opened;
  opened.name = path == "-" ? "<stdin>" : path;
  opened.input = std::make_unique<detail::Input>(path, opened.name);
  detail::Input& input = *opened.input;
  if (!input.ensure(4)) {
    // A *.zst name promises a zstd stream, and one too short for a frame's
    // magic number is not one (zstd -t: unexpected end of file), however
    // harmless an empty plain trace would be.
    if (path.size() > 4 && path.ends_with(".zst")) {
      throw base::FormatError(fmt::format("{}: {} bytes: not a zstd stream (too short for a zstd frame)",
                                          opened.name, input.available()));
    }
    // Said at once, before any option that needs what records hold (levels,
    // units) is checked against an input that has none.
    if (input.available() == 0 && !options.allow_empty) detail::fail_no_records(opened.name);
    return detail::open_plain_records_reader(std::move(opened), options);
  }
  const std::uint32_t magic = detail::load_le32(input.data());
  std::string first_bytes(input.data(), 4);
  if (magic != detail::kHeaderMagic && input.seekable() && detail::ends_with_container_footer(input)) {
    detail::fail_damaged_header_magic(opened.name, first_bytes, "the file");
  }
  if (magic == detail::kHeaderMagic) return detail::open_container_reader(std::move(opened), options);
  if (magic == detail::kZstdMagic || (magic & detail::kSkippableMask) == detail::kHeaderMagic) {
    return detail::open_plain_zstd_reader(std::move(opened), options, std::move(first_bytes));
  }
  return detail::open_plain_records_reader(std::move(opened), options);
}

}  // namespace

std::unique_ptr<TraceReader> TraceReader::open(const std::string& path, const ReaderOptions& options) {
  std::unique_ptr<TraceReader> reader = open_input(path, options);
  if (options.allow_empty) return reader;
  return detail::records_required(std::move(reader));
}

}  // namespace nodetrace::formats
