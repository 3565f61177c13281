// What an output path means for a trace written to it, decided in one place
// for the writer and for the programs that name the record form from the
// file name (tracer render -o t.xdin.zst).
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>

#include "nodetrace/formats/record/record.hpp"

namespace nodetrace::formats {

enum class OutputKind : std::uint8_t {
  Auto,       // container when the path ends in .zst or is "-", else plain
  Container,  // header, markers, data frames, trailer
  Plain,      // records only: text for din / xdin, 8-byte records for binary
};

struct TraceOutput {
  bool container = false;  // else plain records
  RecordForm form = RecordForm::Din;
};

// `kind` Auto: a container for "-" or a name ending in .zst, else plain
// records. The form is `form` when given, else what the name says:
// .xdin / .xdin.zst extended din, .bin / .bin.zst binary, anything else
// (and "-") din.
TraceOutput decide_trace_output(std::string_view path, OutputKind kind = OutputKind::Auto,
                       std::optional<RecordForm> form = std::nullopt);

}  // namespace nodetrace::formats
