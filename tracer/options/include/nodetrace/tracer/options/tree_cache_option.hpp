// --tree-cache DIR of `tracer render` and `tracer info`, and the
// NODETRACE_TREE_CACHE environment variable it overrides: the folder of the
// tree cache (nodetrace/tracer/accel/tree_cache.hpp).
#pragma once

#include <CLI/CLI.hpp>

#include <cstdio>
#include <cstdlib>
#include <memory>
#include <optional>
#include <string>

#include "nodetrace/tracer/accel/tree_cache.hpp"

namespace nodetrace::tracer::tools {

inline void add_tree_cache_option(CLI::App& app, std::optional<std::string>& directory) {
  app.add_option("--tree-cache", directory,
                 "keep built kd-trees and BVHs in DIR and load them instead of building on later runs of the same "
                 "triangles and build options (DIR is created if its parent exists; the trace does not change); "
                 "default: the NODETRACE_TREE_CACHE environment variable; '' for none")
      ->type_name("DIR");
}

// The cache --tree-cache or else NODETRACE_TREE_CACHE names, its notes and
// warnings printed as `program: note: ...`; null when neither names one.
inline std::unique_ptr<TreeCache> open_tree_cache(const std::optional<std::string>& option, const char* program) {
  std::string directory;
  if (option) {
    directory = *option;
  } else if (const char* variable = std::getenv("NODETRACE_TREE_CACHE")) {
    directory = variable;
  }
  if (directory.empty()) return nullptr;
  return std::make_unique<TreeCache>(directory, [program](const TreeCacheMessage& message) {
    std::fprintf(stderr, "%s: %s: %s\n", program,
                 message.level == TreeCacheMessage::Level::Warning ? "warning" : "note", message.text.c_str());
  });
}

}  // namespace nodetrace::tracer::tools
