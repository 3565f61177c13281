// The tree cache (`--tree-cache DIR`, NODETRACE_TREE_CACHE): built kd-trees
// and BVHs kept in a folder and loaded instead of built on the next render of
// the same triangles with the same build options by the same tracer version.
//
// A file is named by the XXH3_128 of its key and holds the whole key, array
// lengths and a checksum of its payload (tree_cache_file.hpp), so a damaged,
// truncated or foreign file is detected, reported as a note, rebuilt and
// replaced. Files are written under a temporary name and renamed into place:
// renders sharing a folder never read a partial file. A loaded structure is
// the built one, node for node, so traces do not depend on the cache; only
// the figures' build times differ (they hold what loading took).
#pragma once

#include <functional>
#include <span>
#include <string>

#include "nodetrace/tracer/accel/acceleration_structure.hpp"

namespace nodetrace::tracer {

struct TreeCacheMessage {
  enum class Level { Note, Warning };
  Level level = Level::Note;
  std::string text;  // e.g. "tree cache DIR/FILE: truncated ...; rebuilt"
};

// Libraries never print: what the cache notices goes to the front end.
using TreeCacheReporter = std::function<void(const TreeCacheMessage&)>;

class TreeCache {
 public:
  // Creates `directory` when it is missing and its parent exists. A folder
  // that cannot be used is reported as a warning now, and obtain() then only
  // builds.
  TreeCache(std::string directory, TreeCacheReporter report);

  const std::string& directory() const { return directory_; }
  bool usable() const { return usable_; }

  // The path of the file that holds the structure of these inputs.
  std::string path_for(std::span<const Triangle> triangles, AccelKind kind, const AccelBuildOptions& options) const;

  // The structure of these inputs: loaded when a good file holds it, else
  // built (AccelerationStructure::build) and stored. Never throws for the
  // cache's sake: a file it cannot read, trust or write is reported and the
  // structure built.
  AccelerationStructure obtain(std::span<const Triangle> triangles, AccelKind kind,
                               const AccelBuildOptions& options) const;

 private:
  void store(const std::string& path, const AccelerationStructure& structure, const std::string& key) const;

  std::string directory_;
  TreeCacheReporter report_;
  bool usable_ = false;
  mutable bool warned_of_writing_ = false;  // one warning for a folder that cannot be written
};

// `cache->obtain(...)`, or a build when there is no cache.
AccelerationStructure build_or_load(const TreeCache* cache, std::span<const Triangle> triangles, AccelKind kind,
                                    const AccelBuildOptions& options);

}  // namespace nodetrace::tracer
