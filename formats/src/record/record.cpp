#include "nodetrace/formats/record/record.hpp"

#include <fmt/format.h>

#include <array>

namespace nodetrace::formats {

std::string_view form_name(RecordForm form) {
  switch (form) {
    case RecordForm::Din: return "din";
    case RecordForm::ExtendedDin: return "xdin";
    case RecordForm::Binary: return "binary";
  }
  return "din";
}

std::optional<RecordForm> parse_form_name(std::string_view name) {
  if (name == "din") return RecordForm::Din;
  if (name == "xdin") return RecordForm::ExtendedDin;
  if (name == "binary") return RecordForm::Binary;
  return std::nullopt;
}

std::optional<RecordForm> form_of_file_name(std::string_view path) {
  const std::string_view name = path.ends_with(".zst") ? path.substr(0, path.size() - 4) : path;
  if (name.ends_with(".xdin")) return RecordForm::ExtendedDin;  // before .din, which it ends with
  if (name.ends_with(".din")) return RecordForm::Din;
  if (name.ends_with(".bin")) return RecordForm::Binary;
  return std::nullopt;
}

char dinero_informat(RecordForm form) {
  switch (form) {
    case RecordForm::Din: return 'd';
    case RecordForm::ExtendedDin: return 'D';
    case RecordForm::Binary: return 'b';
  }
  return 'd';
}

std::string tag_text(Tag tag) {
  if (tag == kTagNone) return {};
  if (tag == kTagPrimitiveList) return "p";
  if (tag == kTagTriangle) return "t";
  return fmt::format("{:02d}", tag);
}

}  // namespace nodetrace::formats
