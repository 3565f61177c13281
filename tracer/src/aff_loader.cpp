// BART AFF (Animated File Format, an NFF extension) loader: a hand-written
// tokenizer over whole-file buffers (the BART scenes are megabytes of numbers),
// a parse into transform nodes and triangle batches, and per-instant
// evaluation of Kochanek-Bartels keyframe splines.
#include <algorithm>
#include <array>
#include <charconv>
#include <cfloat>
#include <cmath>
#include <filesystem>
#include <map>
#include <numbers>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include <fmt/format.h>

#include "nodetrace/tracer/camera_checks.hpp"
#include "nodetrace/tracer/scene_geometry.hpp"
#include "scene_internal.hpp"
#include "triangle_checks.hpp"

namespace nodetrace::tracer::detail {

namespace {

// ---------------------------------------------------------------- math

struct Quat {
  double w = 1, x = 0, y = 0, z = 0;
};

Quat operator*(const Quat& a, const Quat& b) {
  return {a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z, a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
          a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x, a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w};
}
Quat conjugate(const Quat& q) { return {q.w, -q.x, -q.y, -q.z}; }
double dot(const Quat& a, const Quat& b) { return a.w * b.w + a.x * b.x + a.y * b.y + a.z * b.z; }

Quat from_axis_angle(double ax, double ay, double az, double degrees) {
  const double len = std::sqrt(ax * ax + ay * ay + az * az);
  if (!(len > 0)) return {};
  const double half = degrees * std::numbers::pi / 360.0;
  const double s = std::sin(half) / len;
  return {std::cos(half), ax * s, ay * s, az * s};
}

// Logarithm of a unit quaternion: the rotation axis times half the angle.
std::array<double, 3> quat_log(const Quat& q) {
  const double v = std::sqrt(q.x * q.x + q.y * q.y + q.z * q.z);
  if (v < 1e-12) return {0, 0, 0};
  const double angle = std::atan2(v, q.w);
  return {q.x / v * angle, q.y / v * angle, q.z / v * angle};
}

Quat quat_exp(const std::array<double, 3>& a) {
  const double angle = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
  if (angle < 1e-12) return {};
  const double s = std::sin(angle) / angle;
  return {std::cos(angle), a[0] * s, a[1] * s, a[2] * s};
}

Quat slerp(const Quat& a, const Quat& b, double u) {
  const double cosine = std::clamp(dot(a, b), -1.0, 1.0);
  double wa = 1 - u, wb = u;
  const double theta = std::acos(cosine);
  if (std::sin(theta) > 1e-9) {
    wa = std::sin((1 - u) * theta) / std::sin(theta);
    wb = std::sin(u * theta) / std::sin(theta);
  }
  Quat r{wa * a.w + wb * b.w, wa * a.x + wb * b.x, wa * a.y + wb * b.y, wa * a.z + wb * b.z};
  const double n = std::sqrt(dot(r, r));
  return {r.w / n, r.x / n, r.y / n, r.z / n};
}

// Affine transform in double precision: 3x3 linear part and translation.
struct Affine {
  std::array<std::array<double, 4>, 3> m{{{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}}};

  static Affine translation(double x, double y, double z) {
    Affine a;
    a.m[0][3] = x, a.m[1][3] = y, a.m[2][3] = z;
    return a;
  }
  static Affine scaling(double x, double y, double z) {
    Affine a;
    a.m[0][0] = x, a.m[1][1] = y, a.m[2][2] = z;
    return a;
  }
  static Affine rotation(const Quat& q) {
    Affine a;
    const double w = q.w, x = q.x, y = q.y, z = q.z;
    a.m[0] = {1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y), 0};
    a.m[1] = {2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x), 0};
    a.m[2] = {2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y), 0};
    return a;
  }
  Affine operator*(const Affine& o) const {
    Affine r;
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 4; ++j) {
        r.m[i][j] = m[i][0] * o.m[0][j] + m[i][1] * o.m[1][j] + m[i][2] * o.m[2][j] + (j == 3 ? m[i][3] : 0);
      }
    }
    return r;
  }
  Vec3 point(const Vec3& p) const {
    return {static_cast<float>(m[0][0] * p.x + m[0][1] * p.y + m[0][2] * p.z + m[0][3]),
            static_cast<float>(m[1][0] * p.x + m[1][1] * p.y + m[1][2] * p.z + m[1][3]),
            static_cast<float>(m[2][0] * p.x + m[2][1] * p.y + m[2][2] * p.z + m[2][3])};
  }
  Vec3 direction(const Vec3& d) const {
    return {static_cast<float>(m[0][0] * d.x + m[0][1] * d.y + m[0][2] * d.z),
            static_cast<float>(m[1][0] * d.x + m[1][1] * d.y + m[1][2] * d.z),
            static_cast<float>(m[2][0] * d.x + m[2][1] * d.y + m[2][2] * d.z)};
  }
  // Inverse transpose of the linear part (for normals), up to scale.
  Affine normal_matrix() const {
    Affine r;
    // Cofactor matrix = det * inverse transpose; the scale is normalized away.
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) {
        const int i1 = (i + 1) % 3, i2 = (i + 2) % 3, j1 = (j + 1) % 3, j2 = (j + 2) % 3;
        r.m[i][j] = m[i1][j1] * m[i2][j2] - m[i1][j2] * m[i2][j1];
      }
      r.m[i][3] = 0;
    }
    return r;
  }
};

Vec3 normalized_or(const Vec3& v, const Vec3& fallback) {
  const float len = length(v);
  return len > 0 && std::isfinite(len) ? v / len : fallback;
}

Vec3 face_normal(const Vec3& a, const Vec3& b, const Vec3& c) {
  return normalized_or(cross(b - a, c - a), {0, 1, 0});
}

// ------------------------------------------------- Kochanek-Bartels splines

struct Key {
  double time = 0;
  std::array<double, 4> value{};
  double tension = 0, continuity = 0, bias = 0;
};

// Outgoing (source) and incoming (destination) tangent weights of key k for
// the differences to its previous and next key, with the usual correction for
// unevenly spaced keys.
struct TangentWeights {
  double out_prev, out_next, in_prev, in_next;
};

TangentWeights tangent_weights(const std::vector<Key>& keys, std::size_t k) {
  const Key& key = keys[k];
  const double t = key.tension, c = key.continuity, b = key.bias;
  TangentWeights w{(1 - t) * (1 + c) * (1 + b) / 2, (1 - t) * (1 - c) * (1 - b) / 2,
                   (1 - t) * (1 - c) * (1 + b) / 2, (1 - t) * (1 + c) * (1 - b) / 2};
  const std::size_t n = keys.size();
  if (k > 0 && k + 1 < n) {
    const double before = keys[k].time - keys[k - 1].time, after = keys[k + 1].time - keys[k].time;
    if (before + after > 0) {
      const double out_scale = 2 * after / (before + after), in_scale = 2 * before / (before + after);
      w.out_prev *= out_scale, w.out_next *= out_scale;
      w.in_prev *= in_scale, w.in_next *= in_scale;
    }
  }
  return w;
}

// Index i with keys[i].time <= time < keys[i + 1].time, and the fraction u.
std::pair<std::size_t, double> locate(const std::vector<Key>& keys, double time) {
  const auto after = std::upper_bound(keys.begin(), keys.end(), time,
                                      [](double t, const Key& key) { return t < key.time; });
  const std::size_t i = static_cast<std::size_t>(after - keys.begin()) - 1;
  const double span = keys[i + 1].time - keys[i].time;
  return {i, (time - keys[i].time) / span};
}

// Position or scale track: Hermite interpolation with KB tangents.
std::array<double, 3> evaluate_vector(const std::vector<Key>& keys, double time) {
  auto value = [&](std::size_t k) { return std::array<double, 3>{keys[k].value[0], keys[k].value[1], keys[k].value[2]}; };
  if (keys.size() == 1 || time <= keys.front().time) return value(0);
  if (time >= keys.back().time) return value(keys.size() - 1);
  const auto [i, u] = locate(keys, time);
  const std::size_t n = keys.size();
  auto differences = [&](std::size_t k, int axis) {
    const double next = k + 1 < n ? keys[k + 1].value[axis] - keys[k].value[axis] : 0;
    const double prev = k > 0 ? keys[k].value[axis] - keys[k - 1].value[axis] : next;
    return std::pair<double, double>{prev, k + 1 < n ? next : prev};
  };
  const TangentWeights w0 = tangent_weights(keys, i), w1 = tangent_weights(keys, i + 1);
  const double u2 = u * u, u3 = u2 * u;
  const double h00 = 2 * u3 - 3 * u2 + 1, h10 = u3 - 2 * u2 + u, h01 = -2 * u3 + 3 * u2, h11 = u3 - u2;
  std::array<double, 3> result{};
  for (int axis = 0; axis < 3; ++axis) {
    const auto [prev0, next0] = differences(i, axis);
    const auto [prev1, next1] = differences(i + 1, axis);
    const double outgoing = w0.out_prev * prev0 + w0.out_next * next0;
    const double incoming = w1.in_prev * prev1 + w1.in_next * next1;
    result[axis] = h00 * keys[i].value[axis] + h10 * outgoing + h01 * keys[i + 1].value[axis] + h11 * incoming;
  }
  return result;
}

// Rotation track: keys are axis-angle; interpolated as quaternions with squad
// and KB tangents taken in the logarithm space.
class RotationTrack {
 public:
  explicit RotationTrack(std::vector<Key> keys) : keys_(std::move(keys)) {
    for (const Key& key : keys_) {
      Quat q = from_axis_angle(key.value[0], key.value[1], key.value[2], key.value[3]);
      // Keep neighbours in one hemisphere so each segment takes the short way.
      if (!quats_.empty() && dot(quats_.back(), q) < 0) q = {-q.w, -q.x, -q.y, -q.z};
      quats_.push_back(q);
    }
    const std::size_t n = quats_.size();
    for (std::size_t k = 0; k < n; ++k) {
      const auto next = k + 1 < n ? quat_log(conjugate(quats_[k]) * quats_[k + 1]) : std::array<double, 3>{};
      const auto prev = k > 0 ? quat_log(conjugate(quats_[k - 1]) * quats_[k]) : next;
      const auto next_or_prev = k + 1 < n ? next : prev;
      const TangentWeights w = tangent_weights(keys_, k);
      std::array<double, 3> to_outer{}, to_inner{};
      for (int a = 0; a < 3; ++a) {
        const double outgoing = w.out_prev * prev[a] + w.out_next * next_or_prev[a];
        const double incoming = w.in_prev * prev[a] + w.in_next * next_or_prev[a];
        to_outer[a] = (outgoing - next_or_prev[a]) / 2;
        to_inner[a] = (prev[a] - incoming) / 2;
      }
      outgoing_control_.push_back(quats_[k] * quat_exp(to_outer));
      incoming_control_.push_back(quats_[k] * quat_exp(to_inner));
    }
  }

  Quat at(double time) const {
    if (quats_.size() == 1 || time <= keys_.front().time) return quats_.front();
    if (time >= keys_.back().time) return quats_.back();
    const auto [i, u] = locate(keys_, time);
    return slerp(slerp(quats_[i], quats_[i + 1], u),
                 slerp(outgoing_control_[i], incoming_control_[i + 1], u), 2 * u * (1 - u));
  }

 private:
  std::vector<Key> keys_;
  std::vector<Quat> quats_, outgoing_control_, incoming_control_;
};

struct AnimatedTransform {
  std::vector<Key> translation, scale;
  std::optional<RotationTrack> rotation;

  Affine at(double time) const {
    Affine result;
    if (!translation.empty()) {
      const auto t = evaluate_vector(translation, time);
      result = Affine::translation(t[0], t[1], t[2]);
    }
    if (rotation) result = result * Affine::rotation(rotation->at(time));
    if (!scale.empty()) {
      const auto s = evaluate_vector(scale, time);
      result = result * Affine::scaling(s[0], s[1], s[2]);
    }
    return result;
  }
};

// ---------------------------------------------------------------- tokenizer

class Tokenizer {
 public:
  Tokenizer(std::string_view text, std::string file) : text_(text), file_(std::move(file)) {}

  // The next token ("" at the end). `{` and `}` are tokens of their own;
  // `#` and `%` start a comment running to the end of the line.
  std::string_view next() {
    skip_space();
    token_line_ = line_;
    if (pos_ >= text_.size()) return {};
    const std::size_t start = pos_;
    if (text_[pos_] == '{' || text_[pos_] == '}') return text_.substr(pos_++, 1);
    while (pos_ < text_.size()) {
      const char c = text_[pos_];
      if (c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\f' || c == '\v' || c == '#' ||
          c == '%' || c == '{' || c == '}') {
        break;
      }
      ++pos_;
    }
    return text_.substr(start, pos_ - start);
  }

  std::string_view peek() {
    const std::size_t pos = pos_;
    const int line = line_, token_line = token_line_;
    const std::string_view token = next();
    pos_ = pos, line_ = line, token_line_ = token_line;
    return token;
  }

  static std::optional<double> parse_number(std::string_view token) {
    if (!token.empty() && token.front() == '+') token.remove_prefix(1);
    double value = 0;
    const auto [end, error] = std::from_chars(token.data(), token.data() + token.size(), value);
    if (error != std::errc() || end != token.data() + token.size() || token.empty()) return std::nullopt;
    return value;
  }

  double number(std::string_view what) {
    const std::string_view token = next();
    last_token_ = token;
    if (token.empty()) fail("expected " + std::string(what) + ", got the end of the file");
    const auto value = parse_number(token);
    if (!value) fail("expected " + std::string(what) + " (a number), got '" + std::string(token) + "'");
    if (!std::isfinite(*value)) {
      fail("expected " + std::string(what) + " (a finite number), got '" + std::string(token) + "'");
    }
    return *value;
  }

  // A number stored as a float: one beyond FLT_MAX would become inf.
  float real(std::string_view what) {
    const double value = number(what);
    if (std::fabs(value) > FLT_MAX) {
      fail(fmt::format("expected {} (a number of at most {:g} in magnitude), got '{}'", what, FLT_MAX,
                       std::string(last_token_)));
    }
    return static_cast<float>(value);
  }

  Vec3 vec3(std::string_view what) {
    const float x = real(what), y = real(what), z = real(what);
    return {x, y, z};
  }

  // A count of elements that follow in the file, `tokens_per_element`
  // tokens each: each token takes at least two bytes (a character and a
  // separator), so a count the rest of the file cannot hold is an error
  // before anything is allocated for it.
  std::size_t count(std::string_view what, std::size_t limit = 100'000'000, std::size_t tokens_per_element = 0) {
    const std::string_view token = next();
    std::size_t value = 0;
    const auto [end, error] = std::from_chars(token.data(), token.data() + token.size(), value);
    if (token.empty() || error != std::errc() || end != token.data() + token.size() || value > limit) {
      fail("expected " + std::string(what) + " (a non-negative integer), got '" + std::string(token) + "'");
    }
    const std::size_t remaining = text_.size() - pos_;
    if (tokens_per_element > 0 && value > remaining / (2 * tokens_per_element)) {
      fail(fmt::format("{} {} needs at least {} bytes, more than the {} left before the end of the file", what,
                       value, 2 * tokens_per_element * value, remaining));
    }
    return value;
  }

  std::string word(std::string_view what) {
    const std::string_view token = next();
    if (token.empty() || token == "{" || token == "}") {
      fail("expected " + std::string(what) + ", got '" + std::string(token) + "'");
    }
    return std::string(token);
  }

  void expect(std::string_view wanted) {
    const std::string_view token = next();
    if (token != wanted) {
      fail("expected '" + std::string(wanted) + "', got " +
           (token.empty() ? std::string("the end of the file") : "'" + std::string(token) + "'"));
    }
  }

  [[noreturn]] void fail(const std::string& what) const { fail_at(token_line_, what); }
  [[noreturn]] void fail_at(int line, const std::string& what) const {
    throw SceneError(file_ + ":" + std::to_string(line) + ": " + what);
  }

  int line() const { return token_line_; }
  const std::string& file() const { return file_; }

 private:
  void skip_space() {
    while (pos_ < text_.size()) {
      const char c = text_[pos_];
      if (c == '\n') {
        ++line_, ++pos_;
      } else if (c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v') {
        ++pos_;
      } else if (c == '#' || c == '%') {
        while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
      } else {
        break;
      }
    }
  }

  std::string_view text_;
  std::string file_;
  std::string_view last_token_;  // of number()
  std::size_t pos_ = 0;
  int line_ = 1, token_line_ = 1;
};

// ---------------------------------------------------------------- parsed scene

struct Node {
  int parent = -1;
  bool animated = false;
  std::string name;  // animated: the `k` block giving its transform
  Affine local;      // static
};

// Triangles under one transform node with one material, in local coordinates.
struct Batch {
  int node = 0;
  std::uint32_t material = 0;
  std::vector<Vec3> corners;  // three per triangle
  std::vector<Vec3> normals;  // parallel to corners (face normals where the file gave none)
  bool has_vertex_normals = false;
};

struct LightDefinition {
  std::string name;  // animated: moved by the transform of `k name`
  Vec3 position;
  Vec3 color{1, 1, 1};
};

struct View {
  Vec3 from{0, 0, 1}, at{0, 0, 0}, up{0, 1, 0};
  float angle = 45;
};

struct ParsedAff {
  std::string name;
  std::string hash;
  Animation animation;
  std::vector<Node> nodes;
  std::vector<Batch> batches;
  std::vector<Material> materials;
  std::vector<LightDefinition> lights;
  std::optional<View> view;
  std::optional<int> width, height;
  Vec3 background{0, 0, 0};
  Vec3 ambient{0.1f, 0.1f, 0.1f};
  std::map<std::string, AnimatedTransform, std::less<>> transforms;
  std::vector<std::string> warnings;
};

// Include budget: nesting depth, files parsed (each inclusion counts, a file
// included twice is parsed twice) and their bytes, so that files including
// each other many times cannot explode; the BART scenes parse a few hundred
// files and some megabytes.
constexpr int kMaxIncludeDepth = 64;
constexpr std::size_t kMaxIncludedFiles = 100'000;
constexpr std::uint64_t kMaxIncludedBytes = std::uint64_t{1} << 30;
// Triangles a scene may make (spheres and cones make many from few bytes):
// about 2 GB of triangles, normals and kd-tree input.
constexpr std::size_t kMaxTriangles = std::size_t{1} << 24;

class AffParser {
 public:
  explicit AffParser(ParsedAff& out) : out_(out) {
    out_.nodes.push_back({});  // root
    node_stack_.push_back(0);
  }

  void parse_file(const std::filesystem::path& path, const Tokenizer* includer, int depth) {
    if (depth > kMaxIncludeDepth) includer->fail("includes nested too deeply (a cycle?)");
    const std::string key = path.lexically_normal().string();
    auto found = files_.find(key);
    if (found == files_.end()) {
      std::error_code error;
      if (!std::filesystem::is_regular_file(path, error)) {
        if (includer) includer->fail("include file '" + path.string() + "' not found");
        throw SceneError(path.string() + ": cannot open scene file");
      }
      std::string bytes = read_scene_file(path);
      hash_ = fnv1a64(bytes, hash_);
      found = files_.emplace(key, std::move(bytes)).first;
    }
    ++files_parsed_;
    bytes_parsed_ += found->second.size();
    if (includer && (files_parsed_ > kMaxIncludedFiles || bytes_parsed_ > kMaxIncludedBytes)) {
      includer->fail(fmt::format("including '{}' exceeds the include budget of {} files or {} bytes parsed "
                                 "(files including others many times?)",
                                 path.string(), kMaxIncludedFiles, kMaxIncludedBytes));
    }
    Tokenizer tokens(found->second, path.string());
    const std::size_t stack_depth = node_stack_.size();
    parse_commands(tokens, path, depth);
    if (depth == 0 && node_stack_.size() != stack_depth) {
      tokens.fail("end of file inside a transform block: expected '}'");
    }
  }

  std::uint64_t hash() const { return hash_; }
  std::size_t triangles() const { return triangles_; }

 private:
  void parse_commands(Tokenizer& tokens, const std::filesystem::path& path, int depth) {
    for (;;) {
      const std::string_view keyword = tokens.next();
      if (keyword.empty()) return;
      if (keyword == "v") parse_view(tokens);
      else if (keyword == "b") out_.background = tokens.vec3("background colour");
      else if (keyword == "am") out_.ambient = tokens.vec3("ambient light colour");
      else if (keyword == "l") parse_light(tokens);
      else if (keyword == "f") parse_nff_material(tokens);
      else if (keyword == "fm") parse_extended_material(tokens);
      else if (keyword == "p") parse_polygon(tokens, false, false);
      else if (keyword == "pp") parse_polygon(tokens, true, false);
      else if (keyword == "tpp") parse_polygon(tokens, true, true);
      else if (keyword == "tp") parse_polygon(tokens, false, true);
      else if (keyword == "m") parse_mesh(tokens);
      else if (keyword == "s") parse_sphere(tokens);
      else if (keyword == "c") parse_cone(tokens);
      else if (keyword == "i") parse_include(tokens, path, depth);
      else if (keyword == "xs") parse_static_transform(tokens);
      else if (keyword == "x") parse_animated_transform(tokens);
      else if (keyword == "k") parse_keyframes(tokens);
      else if (keyword == "a") parse_animation(tokens);
      else if (keyword == "}") {
        if (node_stack_.size() <= 1) tokens.fail("'}' without a matching transform block");
        node_stack_.pop_back();
      } else {
        tokens.fail("unknown keyword '" + std::string(keyword) +
                    "' (expected one of v b am l f fm p pp tpp tp m s c i xs x k a })");
      }
    }
  }

  void parse_view(Tokenizer& tokens) {
    const int view_line = tokens.line();
    View view;
    for (;;) {
      const std::string_view field = tokens.peek();
      if (field == "from") tokens.next(), view.from = tokens.vec3("view 'from' coordinate");
      else if (field == "at") tokens.next(), view.at = tokens.vec3("view 'at' coordinate");
      else if (field == "up") tokens.next(), view.up = tokens.vec3("view 'up' coordinate");
      else if (field == "angle") {
        tokens.next();
        view.angle = tokens.real("view angle in degrees");
        if (!(view.angle > 0 && view.angle < 180)) {
          tokens.fail(fmt::format("expected a view angle between 0 and 180 degrees, got {:g}", view.angle));
        }
      }
      else if (field == "hither") tokens.next(), tokens.number("hither distance");
      else if (field == "resolution") {
        tokens.next();
        const auto width = tokens.count("horizontal resolution", 1 << 20);
        const auto height = tokens.count("vertical resolution", 1 << 20);
        if (width == 0 || height == 0) {
          tokens.fail(fmt::format("expected a resolution of at least 1x1, got {}x{}", width, height));
        }
        out_.width = static_cast<int>(width), out_.height = static_cast<int>(height);
      } else {
        break;
      }
    }
    switch (camera_problem(view.from, view.at, view.up)) {
      case CameraProblem::EyeAtLookAt:
        tokens.fail_at(view_line, "view 'from' and 'at' are the same point: the camera looks nowhere");
      case CameraProblem::UpAlongView:
        tokens.fail_at(view_line, "view 'up' is parallel to the view direction: expected a direction across it");
      case CameraProblem::None: break;
    }
    out_.view = view;
  }

  void parse_light(Tokenizer& tokens) {
    LightDefinition light;
    if (!Tokenizer::parse_number(tokens.peek())) light.name = tokens.word("light name");
    light.position = tokens.vec3("light position");
    if (Tokenizer::parse_number(tokens.peek())) light.color = tokens.vec3("light colour");
    out_.lights.push_back(std::move(light));
  }

  std::uint32_t add_material(Material material, const Tokenizer& tokens) {
    // Identical definitions (the BART city includes the same colour files
    // hundreds of times) share one entry.
    auto key = std::array<float, 14>{material.diffuse.x, material.diffuse.y, material.diffuse.z,
                                     material.specular.x, material.specular.y, material.specular.z,
                                     material.shininess, material.reflectance, material.transmittance,
                                     material.ior, 0, 0, 0, 0};
    if (material.ambient) {
      key[10] = 1, key[11] = material.ambient->x, key[12] = material.ambient->y, key[13] = material.ambient->z;
    }
    const auto found = material_index_.find(key);
    if (found != material_index_.end()) return found->second;
    material.name = std::filesystem::path(tokens.file()).filename().string() + ":" + std::to_string(tokens.line());
    out_.materials.push_back(std::move(material));
    const auto index = static_cast<std::uint32_t>(out_.materials.size() - 1);
    material_index_.emplace(key, index);
    return index;
  }

  void parse_nff_material(Tokenizer& tokens) {
    const Vec3 color = tokens.vec3("material colour");
    const float kd = tokens.real("diffuse coefficient Kd");
    const float ks = tokens.real("specular coefficient Ks");
    const float shine = tokens.real("Phong exponent Shine");
    const float transmittance = tokens.real("transmittance T");
    const float ior = tokens.real("index of refraction");
    Material material;
    material.diffuse = color * kd;
    material.specular = {ks, ks, ks};
    material.shininess = shine;
    material.reflectance = std::clamp(ks, 0.0f, 1.0f);  // NFF: Ks also weighs the reflected ray
    material.transmittance = std::clamp(transmittance, 0.0f, 1.0f);
    material.ior = ior > 0 ? ior : 1;
    current_material_ = add_material(std::move(material), tokens);
  }

  void parse_extended_material(Tokenizer& tokens) {
    Material material;
    material.ambient = tokens.vec3("ambient colour");
    material.diffuse = tokens.vec3("diffuse colour");
    material.specular = tokens.vec3("specular colour");
    material.shininess = tokens.real("Phong exponent Shine");
    material.transmittance = std::clamp(tokens.real("transmittance T"), 0.0f, 1.0f);
    const float ior = tokens.real("index of refraction");
    material.ior = ior > 0 ? ior : 1;
    const Vec3& s = material.specular;
    material.reflectance = std::clamp((s.x + s.y + s.z) / 3, 0.0f, 1.0f);
    current_material_ = add_material(std::move(material), tokens);
  }

  Batch& batch() {
    const int node = node_stack_.back();
    if (out_.batches.empty() || out_.batches.back().node != node ||
        out_.batches.back().material != current_material_) {
      out_.batches.push_back({node, current_material_, {}, {}, false});
    }
    return out_.batches.back();
  }

  void add_triangle(const Tokenizer& tokens, Batch& target, const Vec3& a, const Vec3& b, const Vec3& c,
                    const Vec3* normals) {
    if (++triangles_ > kMaxTriangles) {
      tokens.fail(fmt::format("the scene makes more than {} triangles (the limit of a scene)", kMaxTriangles));
    }
    if (!checks_.keep({a, b, c, 0}, tokens.file() + ":" + std::to_string(tokens.line()))) return;
    target.corners.insert(target.corners.end(), {a, b, c});
    if (normals) {
      target.normals.insert(target.normals.end(), {normals[0], normals[1], normals[2]});
      target.has_vertex_normals = true;
    } else {
      const Vec3 n = face_normal(a, b, c);
      target.normals.insert(target.normals.end(), {n, n, n});
    }
  }

  void parse_polygon(Tokenizer& tokens, bool with_normals, bool with_texture) {
    const std::size_t count =
        tokens.count("polygon vertex count", 100'000'000, 3 + (with_normals ? 3 : 0) + (with_texture ? 2 : 0));
    if (count < 3) tokens.fail("expected a polygon vertex count of at least 3, got " + std::to_string(count));
    std::vector<Vec3> points(count), normals(with_normals ? count : 0);
    for (std::size_t i = 0; i < count; ++i) {
      points[i] = tokens.vec3("polygon vertex coordinate");
      if (with_normals) normals[i] = tokens.vec3("polygon vertex normal");
      if (with_texture) tokens.number("texture coordinate"), tokens.number("texture coordinate");
    }
    Batch& target = batch();
    for (std::size_t i = 1; i + 1 < count; ++i) {
      const Vec3 fan_normals[3] = {with_normals ? normals[0] : Vec3{}, with_normals ? normals[i] : Vec3{},
                                   with_normals ? normals[i + 1] : Vec3{}};
      add_triangle(tokens, target, points[0], points[i], points[i + 1], with_normals ? fan_normals : nullptr);
    }
  }

  void parse_mesh(Tokenizer& tokens) {
    std::vector<Vec3> vertices, normals;
    std::size_t texture_coordinates = 0;
    bool have_vertices = false, have_triangles = false;
    for (;;) {
      const std::string_view part = tokens.peek();
      if (part == "vertices") {
        tokens.next();
        const std::size_t count = tokens.count("mesh vertex count", 100'000'000, 3);
        vertices.resize(count);
        for (auto& v : vertices) v = tokens.vec3("mesh vertex coordinate");
        have_vertices = true;
      } else if (part == "normals") {
        tokens.next();
        const std::size_t count = tokens.count("mesh normal count", 100'000'000, 3);
        normals.resize(count);
        for (auto& n : normals) n = tokens.vec3("mesh normal coordinate");
      } else if (part == "texturecoords") {
        tokens.next();
        texture_coordinates = tokens.count("mesh texture coordinate count", 100'000'000, 2);
        tokens.word("texture image name");  // never loaded: a node trace needs no textures
        for (std::size_t i = 0; i < 2 * texture_coordinates; ++i) tokens.number("texture coordinate");
      } else if (part == "triangles" || part == "txtriangles") {
        tokens.next();
        if (!have_vertices) tokens.fail("expected 'vertices' before '" + std::string(part) + "' in mesh");
        const bool textured = part == "txtriangles" || texture_coordinates > 0;
        parse_mesh_triangles(tokens, vertices, normals, textured, texture_coordinates);
        have_triangles = true;
      } else {
        break;
      }
    }
    if (!have_triangles) tokens.fail("expected 'triangles' in mesh");
  }

  void parse_mesh_triangles(Tokenizer& tokens, const std::vector<Vec3>& vertices,
                            const std::vector<Vec3>& normals, bool textured, std::size_t texture_count) {
    const std::size_t count = tokens.count("mesh triangle count", 100'000'000,
                                           3 + (normals.empty() ? 0 : 3) + (textured ? 3 : 0));
    Batch& target = batch();
    target.corners.reserve(target.corners.size() + 3 * count);
    target.normals.reserve(target.normals.size() + 3 * count);
    auto index = [&](std::size_t limit, const char* what) {
      const std::size_t value = tokens.count(what);
      if (value >= limit) {
        tokens.fail(std::string("expected ") + what + " below " + std::to_string(limit) + ", got " +
                    std::to_string(value));
      }
      return value;
    };
    for (std::size_t t = 0; t < count; ++t) {
      const std::size_t a = index(vertices.size(), "vertex index"), b = index(vertices.size(), "vertex index"),
                        c = index(vertices.size(), "vertex index");
      if (!normals.empty()) {
        const std::size_t na = index(normals.size(), "normal index"), nb = index(normals.size(), "normal index"),
                          nc = index(normals.size(), "normal index");
        const Vec3 corner_normals[3] = {normals[na], normals[nb], normals[nc]};
        add_triangle(tokens, target, vertices[a], vertices[b], vertices[c], corner_normals);
      } else {
        add_triangle(tokens, target, vertices[a], vertices[b], vertices[c], nullptr);
      }
      if (textured) {
        for (int k = 0; k < 3; ++k) index(std::max<std::size_t>(texture_count, 1), "texture coordinate index");
      }
    }
  }

  void add_closed_mesh(const Tokenizer& tokens, const std::vector<Triangle>& triangles) {
    Batch& target = batch();
    for (const auto& t : triangles) add_triangle(tokens, target, t.v0, t.v1, t.v2, nullptr);
  }

  void parse_sphere(Tokenizer& tokens) {
    const Vec3 center = tokens.vec3("sphere centre coordinate");
    const float radius = tokens.real("sphere radius");
    if (!(radius > 0)) tokens.fail("expected a positive sphere radius");
    add_closed_mesh(tokens, make_sphere_mesh(center, radius, 2));
  }

  void parse_cone(Tokenizer& tokens) {
    const Vec3 base = tokens.vec3("cone base coordinate");
    const float base_radius = tokens.real("cone base radius");
    const Vec3 apex = tokens.vec3("cone apex coordinate");
    const float apex_radius = tokens.real("cone apex radius");
    add_closed_mesh(tokens, make_cone_mesh(base, std::fabs(base_radius), apex, std::fabs(apex_radius), 24));
  }

  void parse_include(Tokenizer& tokens, const std::filesystem::path& path, int depth) {
    tokens.number("include detail level");
    const std::string name = tokens.word("include file name");
    const std::filesystem::path included = std::filesystem::path(name).is_absolute()
                                               ? std::filesystem::path(name)
                                               : path.parent_path() / name;
    parse_file(included, &tokens, depth + 1);
  }

  void open_block(Tokenizer& tokens, Node node) {
    tokens.expect("{");
    node.parent = node_stack_.back();
    out_.nodes.push_back(std::move(node));
    node_stack_.push_back(static_cast<int>(out_.nodes.size() - 1));
  }

  void parse_static_transform(Tokenizer& tokens) {
    const Vec3 scale = tokens.vec3("scale factor");
    const Vec3 axis = tokens.vec3("rotation axis coordinate");
    const float degrees = tokens.real("rotation angle in degrees");
    const Vec3 translation = tokens.vec3("translation");
    Node node;
    node.local = Affine::translation(translation.x, translation.y, translation.z) *
                 Affine::rotation(from_axis_angle(axis.x, axis.y, axis.z, degrees)) *
                 Affine::scaling(scale.x, scale.y, scale.z);
    open_block(tokens, std::move(node));
  }

  void parse_animated_transform(Tokenizer& tokens) {
    Node node;
    node.animated = true;
    node.name = tokens.word("animated transform name");
    open_block(tokens, std::move(node));
  }

  std::vector<Key> parse_keys(Tokenizer& tokens, int values) {
    const std::size_t count = tokens.count("keyframe count", 100'000'000, 4 + static_cast<std::size_t>(values));
    if (count == 0) tokens.fail("expected at least one keyframe");
    std::vector<Key> keys(count);
    for (auto& key : keys) {
      key.time = tokens.number("keyframe time");
      for (int i = 0; i < values; ++i) key.value[i] = tokens.number("keyframe value");
      key.tension = tokens.number("keyframe tension");
      key.continuity = tokens.number("keyframe continuity");
      key.bias = tokens.number("keyframe bias");
    }
    // Some BART tracks (Robot1.aff's) run backwards in time after their
    // last useful key; a search from the first key never reaches those, so
    // they are dropped.
    const auto backwards = std::adjacent_find(keys.begin(), keys.end(),
                                              [](const Key& a, const Key& b) { return b.time < a.time; });
    if (backwards != keys.end()) keys.erase(backwards + 1, keys.end());
    return keys;
  }

  void parse_keyframes(Tokenizer& tokens) {
    const std::string name = tokens.word("keyframe block name");
    tokens.expect("{");
    AnimatedTransform transform;
    for (;;) {
      const std::string_view part = tokens.next();
      if (part == "}") break;
      if (part == "transl") transform.translation = parse_keys(tokens, 3);
      else if (part == "scale") transform.scale = parse_keys(tokens, 3);
      else if (part == "rot") transform.rotation.emplace(parse_keys(tokens, 4));
      else {
        tokens.fail("expected 'transl', 'rot', 'scale' or '}' in keyframe block, got " +
                    (part.empty() ? std::string("the end of the file") : "'" + std::string(part) + "'"));
      }
    }
    out_.transforms.insert_or_assign(name, std::move(transform));
  }

  void parse_animation(Tokenizer& tokens) {
    Animation animation;
    animation.start = tokens.number("animation start time");
    animation.end = tokens.number("animation end time");
    animation.frames = tokens.count("animation frame count", 100'000'000);
    if (animation.frames == 0) tokens.fail("expected an animation frame count of at least 1");
    if (animation.end < animation.start) tokens.fail("expected an animation end time not before its start");
    out_.animation = animation;
  }

  ParsedAff& out_;
  std::vector<int> node_stack_;
  std::uint32_t current_material_ = 0;
  std::map<std::array<float, 14>, std::uint32_t> material_index_;
  std::unordered_map<std::string, std::string> files_;
  std::uint64_t hash_ = kFnvOffset;
  std::size_t files_parsed_ = 0, triangles_ = 0;
  std::uint64_t bytes_parsed_ = 0;
  TriangleChecks checks_;

 public:
  std::vector<std::string> warnings() const {
    if (auto warning = checks_.warning()) return {*warning};
    return {};
  }
};

// ---------------------------------------------------------------- source

class AffSceneSource final : public SceneSource {
 public:
  explicit AffSceneSource(ParsedAff parsed) : parsed_(std::move(parsed)) {}

  const std::string& name() const override { return parsed_.name; }
  const Animation& animation() const override { return parsed_.animation; }
  std::string content_hash() const override { return parsed_.hash; }
  std::vector<std::string> warnings() const override { return parsed_.warnings; }

  Scene at_time(double time) const override {
    // A NaN time would make the key search run off its keys.
    if (!std::isfinite(time)) throw SceneError(parsed_.name + ": scene time " + std::to_string(time) + " is not finite");
    Scene scene;
    scene.name = parsed_.name;
    scene.materials = parsed_.materials;
    scene.background = parsed_.background;
    scene.ambient = parsed_.ambient;
    scene.suggested_width = parsed_.width;
    scene.suggested_height = parsed_.height;

    std::vector<Affine> world(parsed_.nodes.size()), normal(parsed_.nodes.size());
    for (std::size_t i = 0; i < parsed_.nodes.size(); ++i) {
      const Node& node = parsed_.nodes[i];
      const Affine local = node.animated ? transform_at(node.name, time) : node.local;
      world[i] = node.parent < 0 ? local : world[node.parent] * local;
      normal[i] = world[i].normal_matrix();
    }

    std::size_t total = 0;
    bool any_vertex_normals = false;
    for (const Batch& batch : parsed_.batches) {
      total += batch.corners.size() / 3;
      any_vertex_normals = any_vertex_normals || batch.has_vertex_normals;
    }
    scene.triangles.reserve(total);
    if (any_vertex_normals) scene.vertex_normals.reserve(3 * total);
    for (const Batch& batch : parsed_.batches) {
      const Affine& m = world[batch.node];
      for (std::size_t c = 0; c + 2 < batch.corners.size(); c += 3) {
        scene.triangles.push_back({m.point(batch.corners[c]), m.point(batch.corners[c + 1]),
                                   m.point(batch.corners[c + 2]), batch.material});
        // Transforms may carry a vertex out of range (or to inf).
        check_coordinates_in_range(scene.triangles.back(), parsed_.name + " at time " + std::to_string(time));
      }
      if (any_vertex_normals) {
        const Affine& n = normal[batch.node];
        for (const Vec3& v : batch.normals) scene.vertex_normals.push_back(normalized_or(n.direction(v), {0, 1, 0}));
      }
    }
    if (scene.materials.empty()) {
      Material fallback;
      fallback.name = "default";
      scene.materials.push_back(fallback);
    }

    for (const auto& light : parsed_.lights) {
      const Vec3 position = light.name.empty() ? light.position : transform_at(light.name, time).point(light.position);
      scene.lights.push_back({position, light.color});
    }

    std::optional<Camera> camera;
    if (parsed_.view) {
      const View& view = *parsed_.view;
      camera = Camera{view.from, view.at, view.up, view.angle};
    }
    if (const auto found = parsed_.transforms.find("camera"); found != parsed_.transforms.end()) {
      // BART's camera path: the eye follows `transl`, and `rot` turns the
      // default view (looking down -z, y up).
      if (!camera) camera = Camera{};
      const AnimatedTransform& path = found->second;
      if (!path.translation.empty()) {
        const auto t = evaluate_vector(path.translation, time);
        const Vec3 offset = camera->look_at - camera->eye;
        camera->eye = {static_cast<float>(t[0]), static_cast<float>(t[1]), static_cast<float>(t[2])};
        camera->look_at = camera->eye + offset;
      }
      if (path.rotation) {
        const Affine rotation = Affine::rotation(path.rotation->at(time));
        camera->look_at = camera->eye + rotation.direction({0, 0, -1});
        camera->up = rotation.direction({0, 1, 0});
      }
    }
    scene.camera = camera;
    return scene;
  }

 private:
  Affine transform_at(const std::string& name, double time) const {
    const auto found = parsed_.transforms.find(name);
    return found == parsed_.transforms.end() ? Affine{} : found->second.at(time);
  }

  ParsedAff parsed_;
};

}  // namespace

std::unique_ptr<SceneSource> open_aff(const std::filesystem::path& path) {
  ParsedAff parsed;
  parsed.name = path.filename().string();
  AffParser parser(parsed);
  parser.parse_file(path, nullptr, 0);
  if (parser.triangles() == 0) throw SceneError(path.string() + ": no triangles (expected p, pp, tp, tpp, m, s or c)");
  parsed.hash = format_hash(parser.hash());
  parsed.warnings = parser.warnings();
  return std::make_unique<AffSceneSource>(std::move(parsed));
}

}  // namespace nodetrace::tracer::detail
