#include "scene/obj_mesh.hpp"

#include <istream>

namespace nodetrace::tracer::detail {

ObjMesh read_obj_one_thread(std::string_view text, tinyobj::MaterialReader& material_reader) {
  ObjMesh mesh;
  tinyobj::attrib_t attrib;
  std::vector<tinyobj::shape_t> shapes;
  TextStreamBuffer buffer(text);
  std::istream stream(&buffer);
  const bool loaded = tinyobj::LoadObj(&attrib, &shapes, &mesh.materials, &mesh.warnings, &mesh.errors, &stream,
                                       &material_reader, /*triangulate=*/true);
  if (!loaded && mesh.errors.empty()) mesh.errors = "cannot parse OBJ file";
  if (!loaded || !mesh.errors.empty()) return mesh;
  mesh.vertices = std::move(attrib.vertices);
  mesh.normals = std::move(attrib.normals);
  for (const auto& shape : shapes) {
    const auto& m = shape.mesh;
    std::size_t offset = 0;
    for (std::size_t face = 0; face < m.num_face_vertices.size(); ++face) {
      const std::size_t corners = m.num_face_vertices[face];
      // Triangulated: a face that is not a triangle is left out.
      if (corners == 3) {
        if (offset + 3 > m.indices.size()) {
          mesh.errors = "a face has fewer indices than corners";
          return mesh;
        }
        for (std::size_t k = 0; k < 3; ++k) {
          mesh.corners.push_back({m.indices[offset + k].vertex_index, m.indices[offset + k].normal_index});
        }
        mesh.material_ids.push_back(face < m.material_ids.size() ? m.material_ids[face] : -1);
      }
      offset += corners;
    }
  }
  return mesh;
}

}  // namespace nodetrace::tracer::detail
