// CSV as the programs' reports write it (RFC 4180), for the front ends that
// print facts rather than a simulator's rows: tracetool info, tracer info and
// tracer scenes.
#pragma once

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace nodetrace::cli {

// A field quoted when it holds a comma, quote or line break, quotes doubled.
std::string csv_field(const std::string& text);

// One line of fields, ending in a newline.
std::string csv_line(const std::vector<std::string>& fields);

// A JSON object as one table `field,value`: a row per leaf, nested keys
// joined with dots (`header.layout.node_size`), values as in JSON except
// that text is unquoted and an empty object or array is {} or [].
std::string field_value_csv(const nlohmann::json& object);

}  // namespace nodetrace::cli
