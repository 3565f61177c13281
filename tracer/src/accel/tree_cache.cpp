#include "nodetrace/tracer/accel/tree_cache.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <fmt/format.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <optional>
#include <system_error>

#include "accel/tree_cache_file.hpp"
#include "nodetrace/base/error.hpp"
#include "nodetrace/base/output_file.hpp"

namespace nodetrace::tracer {

namespace {

// Closes a descriptor when it goes out of scope.
struct OpenFile {
  int fd;
  ~OpenFile() { ::close(fd); }
};

// The structure in the file at `path`; nullopt when there is none. Throws
// DamagedTreeFile when it is there but cannot be read or trusted.
std::optional<AccelerationStructure> load(const std::string& path, std::string_view key, AccelKind kind,
                                          std::uint64_t triangle_count) {
  const OpenFile file{::open(path.c_str(), O_RDONLY | O_CLOEXEC)};
  if (file.fd < 0) {
    if (errno == ENOENT) return std::nullopt;
    throw DamagedTreeFile(fmt::format("cannot be read: {}", std::strerror(errno)));
  }
  struct stat status{};
  if (::fstat(file.fd, &status) != 0) throw DamagedTreeFile(fmt::format("cannot be read: {}", std::strerror(errno)));
  if (!S_ISREG(status.st_mode)) throw DamagedTreeFile("not a regular file");
  return read_tree_cache_file(file.fd, std::uint64_t(status.st_size), key, kind, triangle_count);
}

}  // namespace

TreeCache::TreeCache(std::string directory, TreeCacheReporter report)
    : directory_(std::move(directory)), report_(std::move(report)) {
  const auto warn = [&](const std::string& why) {
    report_({TreeCacheMessage::Level::Warning,
             fmt::format("tree cache {}: {}; going on without the cache", directory_, why)});
  };
  if (directory_.empty()) {
    warn("an empty folder name");
    return;
  }
  std::error_code error;
  const auto status = std::filesystem::status(directory_, error);
  if (status.type() == std::filesystem::file_type::not_found) {
    // Only the last component is made: a mistyped parent is not created.
    if (!std::filesystem::create_directory(directory_, error) && error) {
      warn(fmt::format("cannot create the folder: {}", error.message()));
      return;
    }
  } else if (error) {
    warn(error.message());
    return;
  } else if (status.type() != std::filesystem::file_type::directory) {
    warn("not a folder");
    return;
  }
  usable_ = true;
}

std::string TreeCache::path_for(std::span<const Triangle> triangles, AccelKind kind,
                                const AccelBuildOptions& options) const {
  return (std::filesystem::path(directory_) / tree_cache_file_name(tree_cache_key(triangles, kind, options))).string();
}

AccelerationStructure TreeCache::obtain(std::span<const Triangle> triangles, AccelKind kind,
                                        const AccelBuildOptions& options) const {
  if (!usable_) return AccelerationStructure::build(triangles, kind, options);
  const auto wall_start = std::chrono::steady_clock::now();
  const std::clock_t cpu_start = std::clock();
  const std::string key = tree_cache_key(triangles, kind, options);
  const std::string path = (std::filesystem::path(directory_) / tree_cache_file_name(key)).string();
  try {
    if (std::optional<AccelerationStructure> loaded = load(path, key, kind, triangles.size())) {
      AccelerationStructure structure = std::move(*loaded);
      set_load_times(structure, std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count(),
                      double(std::clock() - cpu_start) / CLOCKS_PER_SEC);
      return structure;
    }
  } catch (const DamagedTreeFile& damage) {
    report_({TreeCacheMessage::Level::Note, fmt::format("tree cache {}: {}; rebuilt", path, damage.what())});
  } catch (const std::bad_alloc&) {
    report_({TreeCacheMessage::Level::Note, fmt::format("tree cache {}: too large to load; rebuilt", path)});
  }
  AccelerationStructure structure = AccelerationStructure::build(triangles, kind, options);
  store(path, structure, key);
  return structure;
}

void TreeCache::store(const std::string& path, const AccelerationStructure& structure, const std::string& key) const {
  try {
    base::OutputFile file(path);
    file.write(encode_tree_cache_file(structure, key));
    file.commit();
  } catch (const base::IoError& error) {
    // Reading may still work (a read-only shared cache): say it once.
    if (warned_of_writing_) return;
    warned_of_writing_ = true;
    report_({TreeCacheMessage::Level::Warning,
             fmt::format("tree cache {}: cannot store a built tree ({}); going on without storing", directory_,
                         error.what())});
  }
}

AccelerationStructure build_or_load(const TreeCache* cache, std::span<const Triangle> triangles, AccelKind kind,
                                    const AccelBuildOptions& options) {
  return cache ? cache->obtain(triangles, kind, options) : AccelerationStructure::build(triangles, kind, options);
}

}  // namespace nodetrace::tracer
