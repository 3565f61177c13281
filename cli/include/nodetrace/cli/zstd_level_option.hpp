// The `--zstd-level` option of the front ends that write containers (tracer
// render, tracetool convert): one range and one wording in both.
#pragma once

#include <CLI/CLI.hpp>

#include "nodetrace/cli/number_range.hpp"

namespace nodetrace::cli {

// zstd's fast levels down to -7 and its levels up to 22: even the "ultra"
// levels 20-22 use windows of at most 128 MiB, which zstd's decoders (zstdcat)
// and ours accept without being told to allow more.
inline constexpr int kMinZstdLevel = -7;
inline constexpr int kMaxZstdLevel = 22;

// Adds `--zstd-level` bound to `level` (its default shown).
inline CLI::Option* add_zstd_level_option(CLI::App& app, int& level) {
  return app
      .add_option("--zstd-level", level,
                  "zstd level of the trace's data frames, -7 to 22 (higher: smaller and slower)")
      ->check(NumberRange(kMinZstdLevel, kMaxZstdLevel))
      ->capture_default_str();
}

}  // namespace nodetrace::cli
