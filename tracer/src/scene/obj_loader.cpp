// Wavefront OBJ + MTL through tinyobjloader, mapped to Whitted materials.
#include <fmt/format.h>
#include <tiny_obj_loader.h>

#include <algorithm>
#include <cfloat>
#include <charconv>
#include <string_view>
#include <cctype>
#include <cmath>
#include <functional>
#include <future>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "nodetrace/base/huge_pages.hpp"
#include "scene/mtl_checks.hpp"
#include "scene/obj_chunks.hpp"
#include "scene/obj_line_checks.hpp"
#include "scene/obj_mesh.hpp"
#include "scene/scene_internal.hpp"
#include "scene/triangle_checks.hpp"

namespace nodetrace::tracer::detail {

namespace {

// Chunks per load thread: smaller chunks even out the threads' work, and
// each chunk's lists, copied into the file's one at a time, hold less.
constexpr std::size_t kChunksPerThread = 4;

float mean3(const tinyobj::real_t* v) { return static_cast<float>((v[0] + v[1] + v[2]) / 3); }
Vec3 vec3(const tinyobj::real_t* v) {
  return {static_cast<float>(v[0]), static_cast<float>(v[1]), static_cast<float>(v[2])};
}

// MTL illumination models: 3 and 5 are mirrors (reflection from Ks); 4, 6
// and 7 are glass (reflection from Ks plus transmission); a dissolve d < 1
// (or Tr > 0, which tinyobjloader folds into d) makes any material
// transmissive. `Pr` (the PBR extension's roughness, above 0: check_mtl_numbers
// refuses 0) gives a GGX lobe of colour Ks, and Ks is then that lobe's alone:
// no Phong highlight, and no mirror or glass reflectance from it.
Material whitted_material(const tinyobj::material_t& m) {
  Material material;
  material.name = m.name;
  material.diffuse = vec3(m.diffuse);
  material.specular = vec3(m.specular);
  material.shininess = static_cast<float>(m.shininess);
  material.emission = vec3(m.emission);
  material.ior = static_cast<float>(m.ior);  // above 0: check_mtl_numbers refuses the rest
  const bool mirror = m.illum == 3 || m.illum == 5;
  const bool glass = m.illum == 4 || m.illum == 6 || m.illum == 7;
  const bool ggx = m.roughness > 0;
  if (ggx) {
    material.ggx_color = material.specular;
    material.ggx_roughness = static_cast<float>(m.roughness);
    material.specular = {0, 0, 0};
    material.shininess = 0;
  }
  if ((mirror || glass) && !ggx) material.reflectance = std::clamp(mean3(m.specular), 0.0f, 1.0f);
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

// The `mtllib` names of an OBJ file, for the content hash: on each line
// whose first word is `mtllib`, the words after it (words as a stream reads
// them: between white space).
std::vector<std::string> material_libraries(std::string_view obj_text) {
  std::vector<std::string> names;
  const auto blank = [](char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; };
  // Only the lines that hold the keyword are looked at: most files have one or none.
  for (std::size_t at = obj_text.find("mtllib"); at != std::string_view::npos; at = obj_text.find("mtllib", at + 1)) {
    const std::size_t line_start = obj_text.rfind('\n', at) == std::string_view::npos ? 0 : obj_text.rfind('\n', at) + 1;
    const std::size_t line_end = std::min(obj_text.find('\n', at), obj_text.size());
    std::string_view line = obj_text.substr(line_start, line_end - line_start);
    std::vector<std::string_view> words;
    for (std::size_t i = 0; i < line.size();) {
      while (i < line.size() && blank(line[i])) ++i;
      const std::size_t start = i;
      while (i < line.size() && !blank(line[i])) ++i;
      if (i > start) words.push_back(line.substr(start, i - start));
    }
    if (!words.empty() && words[0] == "mtllib" && words[0].data() == obj_text.data() + at) {
      for (std::size_t k = 1; k < words.size(); ++k) names.emplace_back(words[k]);
    }
    at = line_end;
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

std::unique_ptr<SceneSource> open_obj(const std::filesystem::path& path, unsigned threads, bool default_lights) {
  const std::string text = read_scene_file(path, load_threads(threads));
  const std::vector<std::string_view> chunks = split_at_lines(text, kChunksPerThread * load_threads(threads));
  check_obj_lines(chunks, path, threads);
  const std::filesystem::path directory = path.parent_path();
  std::vector<std::string> notes;
  std::vector<std::filesystem::path> hashed_libraries;
  for (const auto& library : material_libraries(text)) {
    std::error_code error;
    if (std::filesystem::is_regular_file(directory / library, error)) {
      hashed_libraries.push_back(directory / library);
      check_mtl_numbers(read_scene_file(directory / library), directory / library);
    } else {
      notes.push_back(path.string() + ": mtllib " + library +
                      ": no such file beside the OBJ file; its materials are missing and their faces get the "
                      "default material");
    }
  }

  std::string base = directory.string();
  if (!base.empty() && base.back() != '/') base += '/';
  tinyobj::MaterialFileReader material_reader(base);
  // In chunks on the threads; a file that uses what the chunks cannot
  // read exactly as LoadObj does (obj_chunks.hpp) on one.
  std::optional<ObjMesh> chunked = read_obj_chunks(chunks, material_reader, threads);
  ObjMesh mesh = chunked ? std::move(*chunked) : read_obj_one_thread(text, material_reader);
  chunked.reset();
  std::string& errors = mesh.errors;
  if (!errors.empty()) {
    while (!errors.empty() && errors.back() == '\n') errors.pop_back();
    throw SceneError(path.string() + ": " + errors);
  }
  // tinyobjloader's warnings (a `usemtl` naming no material, say), each a
  // note; the missing material files are said above, in our words.
  std::istringstream warning_lines(mesh.warnings);
  for (std::string line; std::getline(warning_lines, line);) {
    if (line.empty() || line.starts_with("Material file [") || line.starts_with("Failed to load material file")) {
      continue;
    }
    const bool material = line.find("not found in .mtl") != std::string::npos;
    notes.push_back(path.string() + ": " + line + (material ? " (its faces get the default material)" : ""));
  }
  const std::vector<float>& vertices = mesh.vertices;
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    if (!std::isfinite(vertices[i])) {
      throw SceneError(path.string() + ": vertex " + std::to_string(i / 3 + 1) +
                       " has a coordinate that is not a finite number");
    }
  }

  Scene scene;
  scene.name = path.filename().string();
  for (const auto& m : mesh.materials) scene.materials.push_back(whitted_material(m));
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
    check_index(index, vertices.size(), "vertex");
    const auto at = static_cast<std::size_t>(index) * 3;
    return Vec3{vertices[at], vertices[at + 1], vertices[at + 2]};
  };
  // Normals are kept only when a face gives one: without any, none are made.
  const bool faces_give_normals = std::any_of(mesh.corners.begin(), mesh.corners.end(),
                                              [](const ObjCorner& corner) { return corner.normal >= 0; });
  bool any_normals = false;
  std::vector<Vec3> normals;
  TriangleChecks checks;
  std::optional<std::vector<int>> lines;  // made for the first message only
  std::size_t triangle_index = 0;
  auto where = [&] {
    if (!lines) lines = triangle_lines(text);
    return triangle_index < lines->size()
               ? path.string() + ":" + std::to_string((*lines)[triangle_index])
               : path.string() + ": triangle " + std::to_string(triangle_index + 1);
  };
  const std::function<std::string()> where_function = where;  // made once, not per triangle
  // The hash (one thread by its nature) beside the triangles' assembly,
  // which is one thread's too. The future waits for it even when a check throws.
  std::future<std::uint64_t> hash = std::async(std::launch::async, [&] {
    std::uint64_t state = fnv1a64(text);
    for (const auto& library : hashed_libraries) state = fnv1a64(read_scene_file(library), state);
    return state;
  });
  base::reserve_touched_on_huge_pages(scene.triangles, mesh.material_ids.size(), load_threads(threads));
  for (std::size_t t = 0; t < mesh.material_ids.size(); ++t) {
    const ObjCorner* corners = mesh.corners.data() + 3 * t;
    const int material = mesh.material_ids[t];
    Triangle triangle{vertex(corners[0].vertex), vertex(corners[1].vertex), vertex(corners[2].vertex),
                      material >= 0 && static_cast<std::size_t>(material) < mesh.materials.size()
                          ? static_cast<std::uint32_t>(material)
                          : default_material};
    const bool keep = checks.keep(triangle, where_function);
    ++triangle_index;
    if (!keep) continue;
    if (faces_give_normals) {
      Vec3 face_normal = cross(triangle.v1 - triangle.v0, triangle.v2 - triangle.v0);
      const float face_length = length(face_normal);
      face_normal = face_length > 0 ? face_normal / face_length : Vec3{0, 1, 0};
      for (int k = 0; k < 3; ++k) {
        if (corners[k].normal >= 0) {
          check_index(corners[k].normal, mesh.normals.size(), "normal");
          const auto at = static_cast<std::size_t>(corners[k].normal) * 3;
          const Vec3 n{mesh.normals[at], mesh.normals[at + 1], mesh.normals[at + 2]};
          const float n_length = length(n);
          normals.push_back(n_length > 0 && std::isfinite(n_length) ? n / n_length : face_normal);
          any_normals = true;
        } else {
          normals.push_back(face_normal);
        }
      }
    }
    scene.triangles.push_back(triangle);
  }
  mesh = ObjMesh{};  // freed before the lights and the scene's copies
  if (scene.triangles.empty()) {
    throw SceneError(path.string() + ": no triangles (expected 'f' lines of at least 3 vertices)");
  }
  if (any_normals) scene.vertex_normals = std::move(normals);

  // OBJ has no point lights and no ambient light: a file without an emitter
  // (a face whose material has `Ke`) gets, unless turned off, a key light
  // above one front corner and a dimmer fill light above the opposite one,
  // each half the scene's diagonal outside the bounds, so the model is lit
  // whatever its scale, and ambient 0.1 (Scene's default, as AFF's).
  const bool has_emitter = std::any_of(scene.triangles.begin(), scene.triangles.end(), [&](const Triangle& t) {
    const Vec3& e = scene.materials[t.material].emission;
    return e.x > 0 || e.y > 0 || e.z > 0;
  });
  const Bounds box = scene.bounds();
  if (!default_lights || has_emitter) scene.ambient = {0, 0, 0};
  if (default_lights && !has_emitter && !box.empty()) {
    scene.default_light =
        "the OBJ file gives no light (no face emits): two default point lights, a key light (0.8) and a fill light (0.4) "
        "outside the bounds, and ambient light 0.1 0.1 0.1 (--default-lights none: none of them)";
    notes.push_back(path.string() + ": " + scene.default_light);
    const Vec3 size = box.hi - box.lo;
    const float reach = 0.5f * length(size) + 1e-3f;
    const Vec3 centre = (box.lo + box.hi) * 0.5f;
    scene.lights.push_back({Vec3{box.hi.x + reach, box.hi.y + reach, box.hi.z + reach}, {0.8f, 0.8f, 0.8f}});
    scene.lights.push_back({Vec3{box.lo.x - reach, box.hi.y + reach, centre.z + reach}, {0.4f, 0.4f, 0.4f}});
  }
  if (auto warning = checks.warning()) notes.push_back(std::move(*warning));
  return std::make_unique<StaticSceneSource>(std::move(scene), format_hash(hash.get()), std::move(notes));
}

}  // namespace nodetrace::tracer::detail
