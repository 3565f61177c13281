#include "nodetrace/formats/write/trace_output.hpp"

namespace nodetrace::formats {

TraceOutput decide_trace_output(std::string_view path, OutputKind kind, std::optional<RecordForm> form) {
  const auto ends_with = [&](std::string_view suffix) {
    return path.size() >= suffix.size() && path.substr(path.size() - suffix.size()) == suffix;
  };
  TraceOutput plan;
  plan.container = kind == OutputKind::Container || (kind == OutputKind::Auto && (path == "-" || ends_with(".zst")));
  if (form) {
    plan.form = *form;
  } else if (ends_with(".xdin.zst") || ends_with(".xdin")) {
    plan.form = RecordForm::ExtendedDin;
  } else if (ends_with(".bin.zst") || ends_with(".bin")) {
    plan.form = RecordForm::Binary;
  }
  return plan;
}

}  // namespace nodetrace::formats
