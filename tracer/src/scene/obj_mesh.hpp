// What the OBJ loader takes from tinyobjloader to make a scene: vertices,
// normals, triangles and their materials, however the file was read (on one
// thread through LoadObj, or in chunks on several: obj_chunks.hpp).
#pragma once

#include <tiny_obj_loader.h>

#include <cstdint>
#include <streambuf>
#include <string>
#include <string_view>
#include <vector>

namespace nodetrace::tracer::detail {

// One corner of a triangle: 0-based indices into ObjMesh's arrays, the
// normal -1 when the face gives none.
struct ObjCorner {
  std::int32_t vertex = 0;
  std::int32_t normal = -1;
};

struct ObjMesh {
  std::vector<float> vertices;  // x y z of each `v`
  std::vector<float> normals;   // x y z of each `vn`
  std::vector<ObjCorner> corners;  // three per triangle, in file order
  std::vector<int> material_ids;   // one per triangle: an index into materials, or -1
  std::vector<tinyobj::material_t> materials;
  std::string warnings, errors;  // tinyobjloader's, in its words, one a line
};

// A read-only std::streambuf over text in memory: tinyobjloader reads a
// stream, and an istringstream would copy a file of 100 MB.
class TextStreamBuffer : public std::streambuf {
 public:
  explicit TextStreamBuffer(std::string_view text) {
    char* begin = const_cast<char*>(text.data());  // never written: no put area, no putback
    setg(begin, begin, begin + text.size());
  }
};

// The whole text through tinyobjloader's LoadObj (triangulated) on this
// thread: the reference every other way of reading must equal.
ObjMesh read_obj_one_thread(std::string_view text, tinyobj::MaterialReader& material_reader);

}  // namespace nodetrace::tracer::detail
