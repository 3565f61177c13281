// The bytes of one tree cache file (tree_cache.hpp): a built kd-tree or BVH
// and the key it was built for. Layout, all in the host's byte order (the key
// records the byte order and the structures' sizes, so a file from another
// kind of machine is foreign, never misread):
//
//   magic "NTTREEC\0" (8 bytes), format version (u32), key length (u32),
//   key (the bytes tree_cache_key makes), payload length (u64),
//   payload checksum (XXH3_128 of the payload, 16 bytes), payload.
//
// The payload: the root bounds, the figures (KdTreeStats without the build
// times), then the structure's arrays, each as its element count (u64) and
// its elements' bytes.
#pragma once

#include <cstdint>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>

#include "nodetrace/tracer/accel/acceleration_structure.hpp"

namespace nodetrace::tracer {

// Raised on a file that cannot be trusted; what() says why, for the note.
class DamagedTreeFile : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// What a file of this format version names its structure by: the format
// version, the tracer's version, the byte order and structure sizes, the
// kind, every build option that shapes the tree, and the triangles (their
// count and the XXH3_128 of their bytes).
std::string tree_cache_key(std::span<const Triangle> triangles, AccelKind kind, const AccelBuildOptions& options);

// The file name (in the cache folder) of the structure of `key`: its XXH3_128 in hex.
std::string tree_cache_file_name(std::string_view key);

// The whole file of `structure` built for `key`.
std::string encode_tree_cache_file(const AccelerationStructure& structure, std::string_view key);

// The structure the open file `fd` of `file_size` bytes holds, when it is
// whole and was made for `key` (a `kind` structure over `triangle_count`
// triangles); throws DamagedTreeFile otherwise. Each array is read straight
// into its vector (one pread each, the payload hashed as it comes). The
// figures' build times are 0 (set_load_times gives them what loading took).
AccelerationStructure read_tree_cache_file(int fd, std::uint64_t file_size, std::string_view key, AccelKind kind,
                                           std::uint64_t triangle_count);

// Marks a structure as loaded, its build times the time loading took.
void set_load_times(AccelerationStructure& structure, double wall_seconds, double cpu_seconds);

}  // namespace nodetrace::tracer
