// The `--format` option of every report a program prints (tracer info and
// scenes, tracetool info, cachesim run, dinero-wrap run): one set of names in
// all four programs.
#pragma once

#include <CLI/CLI.hpp>

#include <string>

namespace nodetrace::cli {

// table: readable (the default); csv: one CSV table; json: one JSON document.
inline const std::vector<std::string> kFormatNames = {"table", "csv", "json"};

// Adds `--format` bound to `format` (default "table"); `shapes` says what
// the CSV and JSON hold.
inline CLI::Option* add_format_option(CLI::App& app, std::string& format, const std::string& shapes) {
  return app.add_option("--format", format, "Output: table (readable), csv or json; " + shapes)
      ->check(CLI::IsMember(kFormatNames))
      ->capture_default_str();
}

}  // namespace nodetrace::cli
