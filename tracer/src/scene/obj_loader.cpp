// Wavefront OBJ + MTL through tinyobjloader, mapped to Whitted materials.
#include <fmt/format.h>
#include <tiny_obj_loader.h>

#include <algorithm>
#include <cfloat>
#include <charconv>
#include <string_view>
#include <cmath>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "scene/scene_internal.hpp"
#include "scene/triangle_checks.hpp"

namespace nodetrace::tracer::detail {

namespace {

float mean3(const tinyobj::real_t* v) { return static_cast<float>((v[0] + v[1] + v[2]) / 3); }
Vec3 vec3(const tinyobj::real_t* v) {
  return {static_cast<float>(v[0]), static_cast<float>(v[1]), static_cast<float>(v[2])};
}

// MTL illumination models: 3 and 5 are mirrors (reflection from Ks); 4, 6
// and 7 are glass (reflection from Ks plus transmission); a dissolve d < 1
// (or Tr > 0, which tinyobjloader folds into d) makes any material
// transmissive.
Material whitted_material(const tinyobj::material_t& m) {
  Material material;
  material.name = m.name;
  material.diffuse = vec3(m.diffuse);
  material.specular = vec3(m.specular);
  material.shininess = static_cast<float>(m.shininess);
  material.ior = m.ior > 0 ? static_cast<float>(m.ior) : 1.0f;
  const bool mirror = m.illum == 3 || m.illum == 5;
  const bool glass = m.illum == 4 || m.illum == 6 || m.illum == 7;
  if (mirror || glass) material.reflectance = std::clamp(mean3(m.specular), 0.0f, 1.0f);
  if (m.dissolve < 1) {
    material.transmittance = std::clamp(static_cast<float>(1 - m.dissolve), 0.0f, 1.0f);
  } else if (glass) {
    // Glass with an opaque dissolve: the transmission filter Tf if given,
    // else mostly clear.
    const float filter = mean3(m.transmittance);
    material.transmittance = filter > 0 ? std::clamp(filter, 0.0f, 1.0f) : 0.9f;
  }
  return material;
}

// Calls visit(line_number, keyword, words) for each line of an OBJ text;
// `words` holds what follows the keyword up to a comment.
template <typename Visit>
void for_each_line(const std::string& text, Visit visit) {
  std::size_t line_start = 0;
  std::vector<std::string_view> words;
  for (int line = 1; line_start < text.size(); ++line) {
    std::size_t line_end = text.find('\n', line_start);
    if (line_end == std::string::npos) line_end = text.size();
    std::string_view rest(text.data() + line_start, line_end - line_start);
    line_start = line_end + 1;
    auto next_word = [&rest]() {
      const std::size_t begin = rest.find_first_not_of(" \t\r");
      if (begin == std::string_view::npos) return std::string_view{};
      rest.remove_prefix(begin);
      const std::size_t end = std::min(rest.find_first_of(" \t\r"), rest.size());
      const std::string_view word = rest.substr(0, end);
      rest.remove_prefix(end);
      return word;
    };
    const std::string_view keyword = next_word();
    if (keyword != "v" && keyword != "vn" && keyword != "vt" && keyword != "f") continue;
    words.clear();
    for (std::string_view word = next_word(); !word.empty() && word.front() != '#'; word = next_word()) {
      words.push_back(word);
    }
    visit(line, keyword, words);
  }
}

struct ElementCounts {
  std::int64_t vertices = 0, texcoords = 0, normals = 0;
};

// tinyobjloader reads a malformed or non-finite coordinate as some number
// without complaint, and trusts face indices (an index past the end reads
// past its arrays); check `v`, `vn`, `vt` and `f` lines first so bad input
// is an error naming the line. A positive index counts from the file's
// first element of its kind (as tinyobjloader reads it, so a forward
// reference works), a negative one back from the line.
void check_lines(const std::string& text, const std::filesystem::path& path) {
  auto fail = [&](int line, const std::string& what) {
    throw SceneError(path.string() + ":" + std::to_string(line) + ": " + what);
  };
  ElementCounts total;
  for_each_line(text, [&](int line, std::string_view keyword, const std::vector<std::string_view>& words) {
    if (keyword == "f") return;
    (keyword == "v" ? total.vertices : keyword == "vt" ? total.texcoords : total.normals) += 1;
    for (std::string_view word : words) {
      if (word.front() == '+') word.remove_prefix(1);
      double value = 0;
      const auto [end, error] = std::from_chars(word.data(), word.data() + word.size(), value);
      // tinyobjloader stores floats: beyond FLT_MAX a value becomes inf.
      if (error != std::errc() || end != word.data() + word.size() || !(std::fabs(value) <= FLT_MAX)) {
        fail(line, fmt::format("expected a finite number of at most {:g} in magnitude in '{}' line, got '{}'",
                               FLT_MAX, keyword, word));
      }
    }
  });
  ElementCounts before;  // elements defined above the current line
  for_each_line(text, [&](int line, std::string_view keyword, const std::vector<std::string_view>& words) {
    if (keyword != "f") {
      (keyword == "v" ? before.vertices : keyword == "vt" ? before.texcoords : before.normals) += 1;
      return;
    }
    if (words.size() < 3) {
      fail(line, "expected a face of at least 3 vertices, got " + std::to_string(words.size()));
    }
    for (const std::string_view word : words) {
      // v, v/vt, v//vn or v/vt/vn
      std::string_view parts[3];
      std::size_t part_count = 0;
      bool too_many_parts = false;
      for (std::size_t start = 0;;) {
        const std::size_t slash = word.find('/', start);
        if (part_count == 3) {
          too_many_parts = true;
          break;
        }
        parts[part_count++] = word.substr(start, slash == std::string_view::npos ? std::string_view::npos : slash - start);
        if (slash == std::string_view::npos) break;
        start = slash + 1;
      }
      if (too_many_parts || parts[0].empty()) {
        fail(line, "expected a face vertex such as 3, 3/1, 3//2 or 3/1/2, got '" + std::string(word) + "'");
      }
      static const char* const kWhat[3] = {"vertex", "texture coordinate", "normal"};
      const std::int64_t totals[3] = {total.vertices, total.texcoords, total.normals};
      const std::int64_t above[3] = {before.vertices, before.texcoords, before.normals};
      for (std::size_t k = 0; k < part_count; ++k) {
        if (k > 0 && parts[k].empty()) continue;  // 3//2: no texture coordinate
        std::int64_t index = 0;
        const auto [end, error] = std::from_chars(parts[k].data(), parts[k].data() + parts[k].size(), index);
        if (error != std::errc() || end != parts[k].data() + parts[k].size()) {
          fail(line, std::string("expected an integer ") + kWhat[k] + " index in face vertex '" + std::string(word) +
                         "', got '" + std::string(parts[k]) + "'");
        }
        if (index > 0 ? index > totals[k] : (index == 0 || -index > above[k])) {
          fail(line, fmt::format("{} index {} is out of range ({} {})", kWhat[k], index,
                                 index > 0 ? totals[k] : above[k],
                                 std::string(k == 0 ? "vertices" : k == 1 ? "texture coordinates" : "normals") +
                                     (index > 0 ? "" : " before this line")));
        }
      }
    }
  });
}

// The `mtllib` names of an OBJ file, for the content hash.
std::vector<std::string> material_libraries(const std::string& obj_text) {
  std::vector<std::string> names;
  std::istringstream lines(obj_text);
  std::string line;
  while (std::getline(lines, line)) {
    std::istringstream words(line);
    std::string keyword, name;
    if (words >> keyword && keyword == "mtllib") {
      while (words >> name) names.push_back(name);
    }
  }
  return names;
}

// The line of each triangle the `f` lines make once triangulated (a face of
// n corners makes n - 2), in file order as tinyobjloader returns them; for
// messages only.
std::vector<int> triangle_lines(const std::string& obj_text) {
  std::vector<int> lines;
  std::istringstream input(obj_text);
  std::string line;
  for (int number = 1; std::getline(input, line); ++number) {
    std::istringstream words(line);
    std::string keyword, corner;
    if (!(words >> keyword) || keyword != "f") continue;
    int corners = 0;
    while (words >> corner && corner[0] != '#') ++corners;
    for (int t = 2; t < corners; ++t) lines.push_back(number);
  }
  return lines;
}

}  // namespace

std::unique_ptr<SceneSource> open_obj(const std::filesystem::path& path) {
  const std::string text = read_scene_file(path);
  check_lines(text, path);
  std::uint64_t hash = fnv1a64(text);
  const std::filesystem::path directory = path.parent_path();
  std::vector<std::string> notes;
  for (const auto& library : material_libraries(text)) {
    std::error_code error;
    if (std::filesystem::is_regular_file(directory / library, error)) {
      hash = fnv1a64(read_scene_file(directory / library), hash);
    } else {
      notes.push_back(path.string() + ": mtllib " + library +
                      ": no such file beside the OBJ file; its materials are missing and their faces get the "
                      "default material");
    }
  }

  tinyobj::attrib_t attrib;
  std::vector<tinyobj::shape_t> shapes;
  std::vector<tinyobj::material_t> obj_materials;
  std::string warnings, errors;
  std::istringstream stream(text);
  std::string base = directory.string();
  if (!base.empty() && base.back() != '/') base += '/';
  tinyobj::MaterialFileReader material_reader(base);
  const bool loaded = tinyobj::LoadObj(&attrib, &shapes, &obj_materials, &warnings, &errors, &stream,
                                       &material_reader, /*triangulate=*/true);
  if (!loaded || !errors.empty()) {
    while (!errors.empty() && errors.back() == '\n') errors.pop_back();
    throw SceneError(path.string() + ": " + (errors.empty() ? "cannot parse OBJ file" : errors));
  }
  // tinyobjloader's warnings (a `usemtl` naming no material, say), each a
  // note; the missing material files are said above, in our words.
  std::istringstream warning_lines(warnings);
  for (std::string line; std::getline(warning_lines, line);) {
    if (line.empty() || line.starts_with("Material file [") || line.starts_with("Failed to load material file")) {
      continue;
    }
    const bool material = line.find("not found in .mtl") != std::string::npos;
    notes.push_back(path.string() + ": " + line + (material ? " (its faces get the default material)" : ""));
  }
  for (std::size_t i = 0; i < attrib.vertices.size(); ++i) {
    if (!std::isfinite(attrib.vertices[i])) {
      throw SceneError(path.string() + ": vertex " + std::to_string(i / 3 + 1) +
                       " has a coordinate that is not a finite number");
    }
  }

  Scene scene;
  scene.name = path.filename().string();
  for (const auto& m : obj_materials) scene.materials.push_back(whitted_material(m));
  const auto default_material = static_cast<std::uint32_t>(scene.materials.size());
  Material fallback;
  fallback.name = "default";
  scene.materials.push_back(fallback);

  // tinyobjloader passes out-of-range indices through (e.g. `f 1 2 9` with
  // three vertices): each is checked before use.
  const auto check_index = [&](int index, std::size_t count, const char* what) {
    if (index < 0 || static_cast<std::size_t>(index) >= count / 3) {
      throw SceneError(path.string() + ": a face refers to " + what + " " + std::to_string(index + 1) +
                       " of the file's " + std::to_string(count / 3));
    }
  };
  auto vertex = [&](int index) {
    check_index(index, attrib.vertices.size(), "vertex");
    const auto at = static_cast<std::size_t>(index) * 3;
    return Vec3{static_cast<float>(attrib.vertices[at]), static_cast<float>(attrib.vertices[at + 1]),
                static_cast<float>(attrib.vertices[at + 2])};
  };
  bool any_normals = false;
  std::vector<Vec3> normals;
  TriangleChecks checks;
  const std::vector<int> lines = triangle_lines(text);
  std::size_t triangle_index = 0;
  auto where = [&] {
    return triangle_index < lines.size()
               ? path.string() + ":" + std::to_string(lines[triangle_index])
               : path.string() + ": triangle " + std::to_string(triangle_index + 1);
  };
  for (const auto& shape : shapes) {
    const auto& mesh = shape.mesh;
    std::size_t offset = 0;
    for (std::size_t face = 0; face < mesh.num_face_vertices.size(); ++face) {
      const std::size_t corners = mesh.num_face_vertices[face];
      if (corners == 3) {
        if (offset + 3 > mesh.indices.size()) throw SceneError(path.string() + ": a face has fewer indices than corners");
        const auto& i0 = mesh.indices[offset];
        const auto& i1 = mesh.indices[offset + 1];
        const auto& i2 = mesh.indices[offset + 2];
        const int material = face < mesh.material_ids.size() ? mesh.material_ids[face] : -1;
        Triangle triangle{vertex(i0.vertex_index), vertex(i1.vertex_index), vertex(i2.vertex_index),
                          material >= 0 && static_cast<std::size_t>(material) < obj_materials.size()
                              ? static_cast<std::uint32_t>(material)
                              : default_material};
        const bool keep = checks.keep(triangle, where);
        ++triangle_index;
        if (!keep) {
          offset += corners;
          continue;
        }
        Vec3 face_normal = cross(triangle.v1 - triangle.v0, triangle.v2 - triangle.v0);
        const float face_length = length(face_normal);
        face_normal = face_length > 0 ? face_normal / face_length : Vec3{0, 1, 0};
        for (const auto* index : {&i0, &i1, &i2}) {
          if (index->normal_index >= 0) {
            check_index(index->normal_index, attrib.normals.size(), "normal");
            const auto at = static_cast<std::size_t>(index->normal_index) * 3;
            const Vec3 n{static_cast<float>(attrib.normals[at]), static_cast<float>(attrib.normals[at + 1]),
                         static_cast<float>(attrib.normals[at + 2])};
            const float n_length = length(n);
            normals.push_back(n_length > 0 && std::isfinite(n_length) ? n / n_length : face_normal);
            any_normals = true;
          } else {
            normals.push_back(face_normal);
          }
        }
        scene.triangles.push_back(triangle);
      }
      offset += corners;
    }
  }
  if (scene.triangles.empty()) {
    throw SceneError(path.string() + ": no triangles (expected 'f' lines of at least 3 vertices)");
  }
  if (any_normals) scene.vertex_normals = std::move(normals);

  // OBJ has no lights: a key light above one front corner and a dimmer fill
  // light above the opposite one, each half the scene's diagonal outside
  // the bounds, so the model is lit whatever its scale.
  const Bounds box = scene.bounds();
  if (!box.empty()) {
    const Vec3 size = box.hi - box.lo;
    const float reach = 0.5f * length(size) + 1e-3f;
    const Vec3 centre = (box.lo + box.hi) * 0.5f;
    scene.lights.push_back({Vec3{box.hi.x + reach, box.hi.y + reach, box.hi.z + reach}, {0.8f, 0.8f, 0.8f}});
    scene.lights.push_back({Vec3{box.lo.x - reach, box.hi.y + reach, centre.z + reach}, {0.4f, 0.4f, 0.4f}});
  }
  if (auto warning = checks.warning()) notes.push_back(std::move(*warning));
  return std::make_unique<StaticSceneSource>(std::move(scene), format_hash(hash), std::move(notes));
}

}  // namespace nodetrace::tracer::detail
