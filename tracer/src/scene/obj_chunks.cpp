// An OBJ text read in chunks on several threads, exactly as LoadObj reads it
// whole: a first pass per chunk counts its `v` / `vn` lines and finds its
// `mtllib` / `usemtl` lines, so each chunk knows its index offsets and the
// material at its start; then each chunk is parsed by tinyobjloader's
// callback API with those applied, and the chunks are joined in order.
#include "scene/obj_chunks.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <exception>
#include <istream>
#include <map>
#include <mutex>
#include <set>
#include <stdexcept>
#include <string>
#include <thread>

#include "nodetrace/base/huge_pages.hpp"

namespace nodetrace::tracer::detail {

std::vector<std::string_view> split_at_lines(std::string_view text, std::size_t count) {
  std::vector<std::string_view> chunks;
  std::size_t start = 0;
  for (std::size_t i = 1; i < count && start < text.size(); ++i) {
    const std::size_t target = std::max(start, text.size() / count * i);
    const std::size_t newline = text.find('\n', target);
    if (newline == std::string_view::npos || newline + 1 >= text.size()) break;
    chunks.push_back(text.substr(start, newline + 1 - start));
    start = newline + 1;
  }
  if (start < text.size()) chunks.push_back(text.substr(start));
  return chunks;
}

unsigned load_threads(unsigned requested) {
  return requested > 0 ? requested : std::max(1u, std::thread::hardware_concurrency());
}

void for_each_chunk(std::size_t count, unsigned threads, const std::function<void(std::size_t)>& job) {
  std::vector<std::exception_ptr> errors(count);
  const auto run = [&](std::size_t i) {
    try {
      job(i);
    } catch (...) {
      errors[i] = std::current_exception();
    }
  };
  const std::size_t workers = std::min<std::size_t>(load_threads(threads), count);
  if (workers <= 1) {
    for (std::size_t i = 0; i < count; ++i) run(i);
  } else {
    std::mutex mutex;
    std::size_t next = 0;
    const auto work = [&] {
      for (;;) {
        std::size_t i;
        {
          const std::lock_guard lock(mutex);
          if (next == count) return;
          i = next++;
        }
        run(i);
      }
    };
    std::vector<std::jthread> pool;
    for (std::size_t w = 1; w < workers; ++w) pool.emplace_back(work);
    work();
  }
  for (const auto& error : errors) {
    if (error) std::rethrow_exception(error);
  }
}

namespace {

bool is_space(char c) { return c == ' ' || c == '\t'; }

// A `usemtl` or `mtllib` line, where it falls among its chunk's faces.
struct StateLine {
  bool usemtl = false;      // else mtllib
  std::size_t faces_before = 0;  // `f` lines of the chunk above it
  std::size_t line = 0;          // 1-based, in the chunk
  std::string text;              // usemtl: the name; mtllib: what follows "mtllib "
  int material_after = -1;       // LoadObj's current material after the line
};

// What the first pass finds in a chunk.
struct ChunkScan {
  std::size_t lines = 0, vertices = 0, normals = 0, faces = 0;
  std::vector<StateLine> state_lines;
  bool unsupported = false;  // a feature read_obj_chunks leaves to read_obj_one_thread
};

// LoadObj's parseString: the word after blanks.
std::string first_word(const char* token) {
  token += std::strspn(token, " \t");
  return std::string(token, std::strcspn(token, " \t\r"));
}

// tinyobjloader's SplitString, for `mtllib` names: blanks split, a
// backslash escapes the next character; the last name is kept even when
// empty.
std::vector<std::string> split_names(const std::string& text) {
  std::vector<std::string> names;
  std::string name;
  bool escaping = false;
  for (const char c : text) {
    if (escaping) {
      escaping = false;
    } else if (c == '\\') {
      escaping = true;
      continue;
    } else if (c == ' ') {
      if (!name.empty()) names.push_back(name);
      name.clear();
      continue;
    }
    name += c;
  }
  names.push_back(name);
  return names;
}

// Classifies each line of a chunk as LoadObj does (its lines end at "\n" or
// "\r\n": a lone CR or a NUL, which would end a line or a token apart from
// that, is left to LoadObj).
ChunkScan scan_chunk(std::string_view chunk) {
  ChunkScan scan;
  if (chunk.find('\0') != std::string_view::npos) {
    scan.unsupported = true;
    return scan;
  }
  std::string line;
  for (std::size_t start = 0; start < chunk.size();) {
    std::size_t end = chunk.find('\n', start);
    const std::size_t next = end == std::string_view::npos ? chunk.size() : end + 1;
    if (end == std::string_view::npos) end = chunk.size();
    ++scan.lines;
    std::string_view text = chunk.substr(start, end - start);
    start = next;
    if (!text.empty() && text.back() == '\r') text.remove_suffix(1);
    if (text.find('\r') != std::string_view::npos) {
      scan.unsupported = true;
      return scan;
    }
    const std::size_t blanks = text.find_first_not_of(" \t");
    if (blanks == std::string_view::npos || text[blanks] == '#') continue;
    const char first = text[blanks];
    // Most lines are `v` and `f`: classify them without a copy.
    const char second = blanks + 1 < text.size() ? text[blanks + 1] : '\0';
    if (first == 'v' && is_space(second)) {
      ++scan.vertices;
      continue;
    }
    if (first == 'f' && is_space(second)) {
      ++scan.faces;
      // LoadObj fails on an empty index after a slash ("3/", "3/1/"), which
      // the callback API reads as no index: left to LoadObj, which says so.
      for (std::size_t slash = text.find('/'); slash != std::string_view::npos; slash = text.find('/', slash + 1)) {
        if (slash + 1 == text.size() || is_space(text[slash + 1])) {
          scan.unsupported = true;
          return scan;
        }
      }
      continue;
    }
    line.assign(text.substr(blanks));
    const char* token = line.c_str();
    if (token[0] == 'v' && token[1] == 'n' && is_space(token[2])) {
      ++scan.normals;
    } else if (token[0] == 'v' && token[1] == 't' && is_space(token[2])) {
      continue;
    } else if ((token[0] == 'v' && token[1] == 'w' && is_space(token[2])) ||
               ((token[0] == 'l' || token[0] == 'p') && is_space(token[1]))) {
      scan.unsupported = true;  // LoadObj checks their indices and may fail
      return scan;
    } else if (std::strncmp(token, "usemtl", 6) == 0) {
      scan.state_lines.push_back({true, scan.faces, scan.lines, first_word(token + 6)});
    } else if (std::strncmp(token, "mtllib", 6) == 0 && is_space(token[6])) {
      scan.state_lines.push_back({false, scan.faces, scan.lines, std::string(token + 7)});
    } else if (token[0] == 'g' && is_space(token[1]) && std::string_view(token + 1).find_first_not_of(" \t") ==
                                                             std::string_view::npos) {
      scan.unsupported = true;  // LoadObj warns of it, naming the line
      return scan;
    }
  }
  return scan;
}

// LoadObj's material state through the `mtllib` and `usemtl` lines in file
// order: sets each line's material_after; the warnings and errors in its
// words. Returns the material before each chunk.
std::vector<int> follow_materials(std::vector<ChunkScan>& scans, tinyobj::MaterialReader& reader, ObjMesh& mesh) {
  std::set<std::string> loaded_files;
  std::map<std::string, int> material_map;
  int material = -1;
  std::vector<int> at_start;
  std::size_t lines_before = 0;
  for (auto& scan : scans) {
    at_start.push_back(material);
    for (auto& state : scan.state_lines) {
      if (state.usemtl) {
        const auto it = material_map.find(state.text);
        if (it != material_map.end()) {
          material = it->second;
        } else {
          material = -1;
          mesh.warnings += "material [ '" + state.text + "' ] not found in .mtl\n";
        }
      } else {
        const std::vector<std::string> names = split_names(state.text);
        if (names.empty()) {
          mesh.warnings += "Looks like empty filename for mtllib. Use default material (line " +
                           std::to_string(lines_before + state.line) + ".)\n";
        } else {
          bool found = false;
          for (const auto& name : names) {
            if (loaded_files.count(name) > 0) {
              found = true;
              continue;
            }
            std::string warnings, errors;
            const bool ok = reader(name, &mesh.materials, &material_map, &warnings, &errors);
            mesh.warnings += warnings;
            mesh.errors += errors;
            if (ok) {
              found = true;
              loaded_files.insert(name);
              break;
            }
          }
          if (!found) mesh.warnings += "Failed to load material file(s). Use default material.\n";
        }
      }
      state.material_after = material;
    }
    lines_before += scan.lines;
  }
  return at_start;
}

// Where a chunk's elements go: its offsets among the file's.
struct ChunkPlacement {
  std::size_t vertices_before = 0, normals_before = 0;
  int material_at_start = -1;
};

// A quad of a chunk, split later (its corners may lie in other chunks).
struct PendingQuad {
  std::size_t first_corner = 0;  // of its two triangles in the chunk's corners
  ObjCorner corners[4];
};

// One chunk's parse through the callback API.
struct ChunkParse {
  const ChunkScan* scan = nullptr;
  ChunkPlacement place;
  ObjMesh* mesh = nullptr;  // vertices and normals go straight to their places
  std::size_t vertices = 0, normals = 0, faces = 0, next_state = 0;
  int material = -1;
  std::vector<ObjCorner> corners;
  std::vector<int> material_ids;
  std::vector<PendingQuad> quads;
  bool unsupported = false;

  // tinyobjloader's fixIndex: a positive index counts from the file's first
  // element, a negative one back from the line.
  static std::int64_t resolve(int raw, std::size_t before, std::size_t local) {
    return raw > 0 ? std::int64_t{raw} - 1 : std::int64_t(before + local) + raw;
  }

  void face(const tinyobj::index_t* indices, int count) {
    const auto& states = scan->state_lines;
    while (next_state < states.size() && states[next_state].faces_before <= faces) {
      material = states[next_state++].material_after;
    }
    ++faces;
    if (count != 3 && count != 4) {
      unsupported = true;  // LoadObj's polygon triangulation is its own
      return;
    }
    ObjCorner corner[4];
    for (int k = 0; k < count; ++k) {
      // No vertex index (a `#` after the corners, which LoadObj rejects):
      // left to LoadObj.
      if (indices[k].vertex_index == 0) unsupported = true;
      const std::int64_t vertex = resolve(indices[k].vertex_index, place.vertices_before, vertices);
      const std::int64_t normal =
          indices[k].normal_index == 0 ? -1 : resolve(indices[k].normal_index, place.normals_before, normals);
      // A quad is split by its corners' positions, which LoadObj knows
      // only for vertices above the group's end: leave a reference ahead to it.
      if (count == 4 && vertex >= std::int64_t(place.vertices_before + vertices)) unsupported = true;
      corner[k] = {static_cast<std::int32_t>(vertex), static_cast<std::int32_t>(normal)};
    }
    if (count == 4) quads.push_back({corners.size(), {corner[0], corner[1], corner[2], corner[3]}});
    corners.insert(corners.end(), {corner[0], corner[1], corner[2]});
    material_ids.push_back(material);
    if (count == 4) {
      corners.insert(corners.end(), {corner[0], corner[2], corner[3]});
      material_ids.push_back(material);
    }
  }
};

void parse_chunk(std::string_view chunk, ChunkParse& parse) {
  tinyobj::callback_t callbacks;
  callbacks.vertex_cb = [](void* data, tinyobj::real_t x, tinyobj::real_t y, tinyobj::real_t z, tinyobj::real_t) {
    auto& p = *static_cast<ChunkParse*>(data);
    if (p.vertices < p.scan->vertices) {
      float* at = p.mesh->vertices.data() + 3 * (p.place.vertices_before + p.vertices);
      at[0] = x, at[1] = y, at[2] = z;
    }
    ++p.vertices;
  };
  callbacks.normal_cb = [](void* data, tinyobj::real_t x, tinyobj::real_t y, tinyobj::real_t z) {
    auto& p = *static_cast<ChunkParse*>(data);
    if (p.normals < p.scan->normals) {
      float* at = p.mesh->normals.data() + 3 * (p.place.normals_before + p.normals);
      at[0] = x, at[1] = y, at[2] = z;
    }
    ++p.normals;
  };
  callbacks.index_cb = [](void* data, tinyobj::index_t* indices, int count) {
    static_cast<ChunkParse*>(data)->face(indices, count);
  };
  // A triangle a face at least (a quad makes two): the lists grow once at most.
  parse.corners.reserve(3 * parse.scan->faces);
  parse.material_ids.reserve(parse.scan->faces);
  TextStreamBuffer buffer(chunk);
  std::istream stream(&buffer);
  // No material reader and no usemtl callback: the chunk's own material
  // state is not LoadObj's (follow_materials is); no warnings wanted.
  tinyobj::LoadObjWithCallback(stream, callbacks, &parse, nullptr, nullptr, nullptr);
  // The scan and tinyobjloader must agree on every line's kind.
  if (parse.vertices != parse.scan->vertices || parse.normals != parse.scan->normals ||
      parse.faces != parse.scan->faces) {
    parse.unsupported = true;
  }
}

// LoadObj's split of a quad: along the shorter diagonal (in floats), 0-2
// when shorter, else 1-3. A near tie, which rounding (or a fused
// multiply-add in tinyobjloader's build) could decide either way, is left to
// LoadObj. Returns false for it.
bool split_quad(const PendingQuad& quad, const std::vector<float>& vertices, ObjCorner* triangles) {
  const auto at = [&](int k) { return vertices.data() + 3 * static_cast<std::size_t>(quad.corners[k].vertex); };
  const float *v0 = at(0), *v1 = at(1), *v2 = at(2), *v3 = at(3);
  const float e02x = v2[0] - v0[0], e02y = v2[1] - v0[1], e02z = v2[2] - v0[2];
  const float e13x = v3[0] - v1[0], e13y = v3[1] - v1[1], e13z = v3[2] - v1[2];
  const float sqr02 = e02x * e02x + e02y * e02y + e02z * e02z;
  const float sqr13 = e13x * e13x + e13y * e13y + e13z * e13z;
  const double exact02 = double(e02x) * e02x + double(e02y) * e02y + double(e02z) * e02z;
  const double exact13 = double(e13x) * e13x + double(e13y) * e13y + double(e13z) * e13z;
  if (std::fabs(exact02 - exact13) <= 1e-5 * std::max(exact02, exact13) || !std::isfinite(exact02 + exact13)) {
    return false;
  }
  const ObjCorner* c = quad.corners;
  const ObjCorner split[6] = {c[0], c[1], c[2], c[0], c[2], c[3]};
  const ObjCorner other[6] = {c[0], c[1], c[3], c[1], c[2], c[3]};
  std::copy_n(sqr02 < sqr13 ? split : other, 6, triangles);
  return true;
}

}  // namespace

std::optional<ObjMesh> read_obj_chunks(std::span<const std::string_view> chunks, tinyobj::MaterialReader& material_reader,
                                       unsigned threads) {
  for (std::size_t i = 0; i + 1 < chunks.size(); ++i) {
    if (chunks[i].empty() || chunks[i].back() != '\n') throw std::invalid_argument("read_obj_chunks: a chunk must end a line");
  }
  std::vector<ChunkScan> scans(chunks.size());
  for_each_chunk(chunks.size(), threads, [&](std::size_t i) { scans[i] = scan_chunk(chunks[i]); });
  ObjMesh mesh;
  std::vector<ChunkPlacement> places(chunks.size());
  std::size_t vertices = 0, normals = 0;
  for (std::size_t i = 0; i < chunks.size(); ++i) {
    if (scans[i].unsupported) return std::nullopt;
    places[i].vertices_before = vertices;
    places[i].normals_before = normals;
    vertices += scans[i].vertices;
    normals += scans[i].normals;
  }
  const std::vector<int> materials_at_start = follow_materials(scans, material_reader, mesh);
  base::reserve_touched_on_huge_pages(mesh.vertices, 3 * vertices, load_threads(threads));
  base::reserve_touched_on_huge_pages(mesh.normals, 3 * normals, load_threads(threads));
  mesh.vertices.resize(3 * vertices);
  mesh.normals.resize(3 * normals);

  std::vector<ChunkParse> parses(chunks.size());
  for_each_chunk(chunks.size(), threads, [&](std::size_t i) {
    ChunkParse& parse = parses[i];
    parse.scan = &scans[i];
    parse.place = places[i];
    parse.place.material_at_start = parse.material = materials_at_start[i];
    parse.mesh = &mesh;
    parse_chunk(chunks[i], parse);
  });
  std::size_t triangles = 0;
  for (const auto& parse : parses) {
    if (parse.unsupported) return std::nullopt;
    triangles += parse.material_ids.size();
  }
  // Quads, now that every vertex is in place; then the chunks in order.
  std::vector<char> tie(chunks.size(), 0);
  for_each_chunk(chunks.size(), threads, [&](std::size_t i) {
    for (const auto& quad : parses[i].quads) {
      if (!split_quad(quad, mesh.vertices, parses[i].corners.data() + quad.first_corner)) tie[i] = 1;
    }
  });
  if (std::find(tie.begin(), tie.end(), 1) != tie.end()) return std::nullopt;
  base::reserve_touched_on_huge_pages(mesh.corners, 3 * triangles, load_threads(threads));
  base::reserve_touched_on_huge_pages(mesh.material_ids, triangles, load_threads(threads));
  for (auto& parse : parses) {
    mesh.corners.insert(mesh.corners.end(), parse.corners.begin(), parse.corners.end());
    mesh.material_ids.insert(mesh.material_ids.end(), parse.material_ids.begin(), parse.material_ids.end());
    parse = ChunkParse{};  // each chunk's lists freed as soon as copied
  }
  return mesh;
}

}  // namespace nodetrace::tracer::detail
