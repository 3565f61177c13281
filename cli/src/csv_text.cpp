#include "nodetrace/cli/csv_text.hpp"

namespace nodetrace::cli {

namespace {

// A JSON pointer ("/header/layout/node_size") as dotted keys
// ("header.layout.node_size"), its escapes (~1 for /, ~0 for ~) undone.
std::string dotted(const std::string& pointer) {
  std::string out;
  for (std::size_t i = 1; i < pointer.size(); ++i) {
    if (pointer[i] == '/') {
      out += '.';
    } else if (pointer[i] == '~' && i + 1 < pointer.size()) {
      out += pointer[++i] == '1' ? '/' : '~';
    } else {
      out += pointer[i];
    }
  }
  return out;
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
  const nlohmann::json flat = object.flatten();  // kept: items() refers to it
  for (const auto& [field, value] : flat.items()) {
    out += csv_line({dotted(field), value.is_string() ? value.get<std::string>() : value.dump()});
  }
  return out;
}

}  // namespace nodetrace::cli
