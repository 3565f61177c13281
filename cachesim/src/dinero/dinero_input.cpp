// Which record form `cachesim dinero` reads, and what it says when the
// trace is not in the form -informat names.
#include <fmt/format.h>

#include <string>

#include "nodetrace/base/error.hpp"
#include "nodetrace/cachesim/dinero/command_line.hpp"

namespace nodetrace::cachesim {

namespace {

char informat_letter(formats::RecordForm form) {
  switch (form) {
    case formats::RecordForm::Din: return 'd';
    case formats::RecordForm::ExtendedDin: return 'D';
    case formats::RecordForm::Binary: return 'b';
  }
  return 'D';
}

}  // namespace

void match_trace_form(DineroOptions& options, const formats::TraceReader& reader) {
  // Plain input is read in the form -informat names; only a container
  // carries its own.
  if (reader.input_kind() != "container" || reader.form() == options.form) return;
  const char letter = informat_letter(reader.form());
  if (options.informat_given) {
    throw base::UsageError(fmt::format(
        "-informat {}: {} is a {} container, whose records are read as {} (-informat {}); give "
        "-informat {} or leave -informat out",
        options.informat, reader.source_name(), formats::form_name(reader.form()),
        formats::form_name(reader.form()), letter, letter));
  }
  options.informat = letter;
  options.form = reader.form();
}

std::string with_informat_hint(const DineroOptions& options, const std::string& message) {
  // Dinero IV's own advice when extended din input has a bad type, which is
  // what din (Dinero III) text read with the default -informat D gives;
  // not for bytes that are not text (the reader's hint names -informat b).
  if (options.informat != 'D' || message.find("unknown access type") == std::string::npos ||
      message.find("so the input is not text") != std::string::npos) {
    return message;
  }
  return message + " (consider -informat d for Dinero III input format)";
}

}  // namespace nodetrace::cachesim
