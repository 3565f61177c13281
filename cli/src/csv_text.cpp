#include "nodetrace/cli/csv_text.hpp"

namespace nodetrace::cli {

namespace {

// One row per leaf of `value`, nested keys and array indexes joined with
// dots (`header.layout.node_size`). An empty object or array is a leaf,
// shown as {} or [] (nlohmann's flatten() makes it null, which a reader
// would take for a missing value).
void add_leaves(const std::string& field, const nlohmann::json& value, std::string& out) {
  if (value.is_structured() && !value.empty()) {
    for (const auto& [key, child] : value.items()) add_leaves(field.empty() ? key : field + "." + key, child, out);
    return;
  }
  out += csv_line({field, value.is_string() ? value.get<std::string>() : value.dump()});
}

}  // namespace

std::string csv_field(const std::string& text) {
  if (text.find_first_of(",\"\r\n") == std::string::npos) return text;
  std::string quoted = "\"";
  for (const char c : text) {
    if (c == '"') quoted += '"';
    quoted += c;
  }
  return quoted + '"';
}

std::string csv_line(const std::vector<std::string>& fields) {
  std::string line;
  for (std::size_t i = 0; i < fields.size(); ++i) {
    if (i > 0) line += ',';
    line += csv_field(fields[i]);
  }
  line += '\n';
  return line;
}

std::string field_value_csv(const nlohmann::json& object) {
  std::string out = "field,value\n";
  for (const auto& [key, value] : object.items()) add_leaves(key, value, out);
  return out;
}

}  // namespace nodetrace::cli
