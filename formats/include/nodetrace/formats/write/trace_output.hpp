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
// records. The form is `form` when given, else what the name says
// (form_of_file_name), else (any other name, and "-") din.
TraceOutput decide_trace_output(std::string_view path, OutputKind kind = OutputKind::Auto,
                       std::optional<RecordForm> form = std::nullopt);

// The record form of an output, the same rule in every program: `named`
// (the --records option) when given, else what the file name says
// (form_of_file_name), else `unnamed` (tracer: din; tracetool: the input's).
// Throws base::UsageError when `named` and the name say different forms.
RecordForm choose_output_form(std::string_view path, std::optional<RecordForm> named, RecordForm unnamed);

}  // namespace nodetrace::formats
