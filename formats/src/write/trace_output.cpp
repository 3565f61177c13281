#include "nodetrace/formats/write/trace_output.hpp"

#include <fmt/format.h>

#include "nodetrace/base/error.hpp"

namespace nodetrace::formats {

TraceOutput decide_trace_output(std::string_view path, OutputKind kind, std::optional<RecordForm> form) {
  TraceOutput plan;
  plan.container = kind == OutputKind::Container || (kind == OutputKind::Auto && (path == "-" || path.ends_with(".zst")));
  plan.form = form.value_or(form_of_file_name(path).value_or(RecordForm::Din));
  return plan;
}

RecordForm choose_output_form(std::string_view path, std::optional<RecordForm> named, RecordForm unnamed) {
  const std::optional<RecordForm> by_name = form_of_file_name(path);
  if (named && by_name && *named != *by_name) {
    throw base::UsageError(fmt::format("{}: the name says {} records, --records says {}: give a name that "
                                       "matches (.din.zst, .xdin.zst, .bin.zst, or without .zst for plain "
                                       "records), or leave --records out",
                                       path, form_name(*by_name), form_name(*named)));
  }
  return named.value_or(by_name.value_or(unnamed));
}

}  // namespace nodetrace::formats
