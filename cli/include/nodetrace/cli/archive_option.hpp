// The `--archive` flag of the front ends that write containers (tracetool
// convert, tracer render): one definition, so both word it alike.
#pragma once

#include <CLI/CLI.hpp>

#include <string>

namespace nodetrace::cli {

// Adds `--archive` to `app`; it excludes `level_option` (the command's
// --zstd-level) and, when given, `frame_records_option`.
inline CLI::Option* add_archive_flag(CLI::App& app, bool& archive, CLI::Option* level_option,
                                     CLI::Option* frame_records_option = nullptr) {
  CLI::Option* flag = app.add_flag("--archive", archive,
                                   "compress for size: zstd level 17 with a 64 MiB window and long-distance "
                                   "matching, 4194304 records per data frame (a reader needs up to 64 MiB per "
                                   "data frame; much slower to write)");
  flag->excludes(level_option);
  if (frame_records_option) flag->excludes(frame_records_option);
  return flag;
}

}  // namespace nodetrace::cli
