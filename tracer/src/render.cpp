#include "nodetrace/tracer/render.hpp"

#include <algorithm>
#include <atomic>
#include <bit>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstring>
#include <exception>
#include <limits>
#include <mutex>
#include <stdexcept>
#include <system_error>
#include <thread>

#include "nodetrace/tracer/interaction.hpp"
#include "watertight_intersection.hpp"

namespace nodetrace::tracer {

using formats::Record;

std::string_view pixel_order_name(PixelOrder order) {
  switch (order) {
    case PixelOrder::Scanline: return "scanline";
    case PixelOrder::Tiled: return "tiled";
    case PixelOrder::Morton: return "morton";
  }
  return "scanline";
}

std::optional<PixelOrder> parse_pixel_order(std::string_view name) {
  for (auto order : {PixelOrder::Scanline, PixelOrder::Tiled, PixelOrder::Morton}) {
    if (pixel_order_name(order) == name) return order;
  }
  return std::nullopt;
}

std::string_view ray_kind_name(RayKind kind) {
  switch (kind) {
    case RayKind::Primary: return "primary";
    case RayKind::Shadow: return "shadow";
    case RayKind::Reflection: return "reflection";
    case RayKind::Refraction: return "refraction";
  }
  return "primary";
}

namespace {

std::uint32_t morton_part(std::uint32_t x) {
  x &= 0xFFFF;
  x = (x | (x << 8)) & 0x00FF00FF;
  x = (x | (x << 4)) & 0x0F0F0F0F;
  x = (x | (x << 2)) & 0x33333333;
  x = (x | (x << 1)) & 0x55555555;
  return x;
}

std::uint32_t morton_unpart(std::uint32_t x) {
  x &= 0x55555555;
  x = (x | (x >> 1)) & 0x33333333;
  x = (x | (x >> 2)) & 0x0F0F0F0F;
  x = (x | (x >> 4)) & 0x00FF00FF;
  x = (x | (x >> 8)) & 0x0000FFFF;
  return x;
}

}  // namespace

std::vector<std::uint32_t> pixel_sequence(int width, int height, PixelOrder order, int tile_size) {
  std::vector<std::uint32_t> sequence;
  if (width <= 0 || height <= 0) return sequence;
  sequence.reserve(static_cast<std::size_t>(width) * height);
  const auto index = [width](int x, int y) { return static_cast<std::uint32_t>(y * width + x); };
  switch (order) {
    case PixelOrder::Scanline:
      for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) sequence.push_back(index(x, y));
      break;
    case PixelOrder::Tiled: {
      const int t = std::max(1, tile_size);
      for (int ty = 0; ty < height; ty += t)
        for (int tx = 0; tx < width; tx += t)
          for (int y = ty; y < std::min(height, ty + t); ++y)
            for (int x = tx; x < std::min(width, tx + t); ++x) sequence.push_back(index(x, y));
      break;
    }
    case PixelOrder::Morton: {
      // Walk the Z-order curve of the enclosing power-of-two square and keep
      // the codes that fall inside the image.
      const auto side = std::bit_ceil(static_cast<std::uint32_t>(std::max(width, height)));
      const std::uint64_t codes = std::uint64_t{side} * side;
      for (std::uint64_t code = 0; code < codes; ++code) {
        const auto x = static_cast<int>(morton_unpart(static_cast<std::uint32_t>(code)));
        const auto y = static_cast<int>(morton_unpart(static_cast<std::uint32_t>(code >> 1)));
        if (x < width && y < height) sequence.push_back(index(x, y));
      }
      break;
    }
  }
  (void)morton_part;
  return sequence;
}

RayKindPlan plan_ray_kinds(const Scene& scene, int max_depth) {
  RayKindPlan plan;
  plan.cast[0] = true;
  bool reflects = false, transmits = false;
  // Only the materials some triangle uses count.
  std::vector<bool> used(scene.materials.size(), false);
  for (const auto& t : scene.triangles) {
    if (t.material < used.size()) used[t.material] = true;
  }
  for (std::size_t i = 0; i < scene.materials.size(); ++i) {
    if (!used[i]) continue;
    const Material& m = scene.materials[i];
    reflects = reflects || m.reflectance > 0 || m.transmittance > 0;  // Fresnel and TIR reflect too
    transmits = transmits || m.transmittance > 0;
  }
  plan.cast[1] = !scene.lights.empty();
  if (!plan.cast[1]) plan.why_not[1] = "scene has no light";
  plan.cast[2] = reflects && max_depth > 1;
  if (!plan.cast[2]) {
    plan.why_not[2] = !reflects ? "no material reflects or transmits" : "max_depth is 1";
  }
  plan.cast[3] = transmits && max_depth > 1;
  if (!plan.cast[3]) plan.why_not[3] = !transmits ? "no material transmits" : "max_depth is 1";
  return plan;
}

RenderStats& RenderStats::operator+=(const RenderStats& other) {
  for (int k = 0; k < kRayKindCount; ++k) rays[k] += other.rays[k];
  node_fetches += other.node_fetches;
  leaf_visits += other.leaf_visits;
  triangle_tests += other.triangle_tests;
  records += other.records;
  return *this;
}

Camera default_camera(const Bounds& bounds) {
  Camera camera;
  if (bounds.empty()) return camera;
  const Vec3 center = (bounds.lo + bounds.hi) * 0.5f;
  const float half_diagonal = length(bounds.hi - bounds.lo) * 0.5f;
  const float radius = half_diagonal > 0 ? half_diagonal : 1e-6f;  // a single point: any small distance
  camera.fov_y_degrees = 45;
  const float distance = radius / std::sin(camera.fov_y_degrees * 0.5f * 3.14159265f / 180.0f);
  camera.eye = center + normalize(Vec3{0.35f, 0.3f, 1.0f}) * distance;
  camera.look_at = center;
  camera.up = {0, 1, 0};
  return camera;
}

std::optional<Hit> intersect_triangle(const Ray& ray, const Triangle& triangle, float t_max) {
  Hit hit;
  if (detail::intersect_sheared(detail::ShearedRay(ray), triangle, t_max, hit)) return hit;
  return std::nullopt;
}

namespace {

// Slab test with the conservative rounding of Ize (2013) so a ray grazing the
// root box is not lost.
bool intersect_box(const Bounds& box, const Vec3& origin, const Vec3& inverse, float& t0,
                   float& t1) {
  constexpr float kGrow = 1.0f + 2.0f * 3.0f * std::numeric_limits<float>::epsilon();
  t0 = 0.0f;
  for (int axis = 0; axis < 3; ++axis) {
    float near = (box.lo[axis] - origin[axis]) * inverse[axis];
    float far = (box.hi[axis] - origin[axis]) * inverse[axis];
    if (near > far) std::swap(near, far);
    far *= kGrow;
    // NaN (0 * inf) leaves the bound as it was.
    t0 = near > t0 ? near : t0;
    t1 = far < t1 ? far : t1;
    if (t0 > t1) return false;
  }
  return true;
}

Vec3 reflect(const Vec3& d, const Vec3& n) { return d - n * (2.0f * dot(d, n)); }

// Unpolarised Fresnel reflectance of a dielectric; cos_i and cos_t positive.
float fresnel_dielectric(float cos_i, float cos_t, float eta_i, float eta_t) {
  const float parallel = (eta_t * cos_i - eta_i * cos_t) / (eta_t * cos_i + eta_i * cos_t);
  const float perpendicular = (eta_i * cos_i - eta_t * cos_t) / (eta_i * cos_i + eta_t * cos_t);
  return 0.5f * (parallel * parallel + perpendicular * perpendicular);
}

}  // namespace

// What one worker carries while it renders a chunk. A ray tree of depth D
// may hold up to 2^D rays (reflection and refraction at every hit), so its
// records are not kept whole: once `records` holds flush_at, `flush`
// hands them on in order (waiting, with threads, until every earlier chunk
// has been emitted). Memory per pixel is the recursion, O(max depth).
struct Renderer::Context {
  std::vector<Record>* records = nullptr;
  RenderStats stats;
  std::function<void()> flush;
  std::uint64_t flushed = 0;  // records already handed on
  std::size_t flush_at = 0;
  void maybe_flush() {
    if (records && flush && records->size() >= flush_at) flush();
  }
};

namespace {
// Unwinds a worker whose render was abandoned because another one failed.
struct RenderCancelled {};
}  // namespace

Renderer::Renderer(const Scene& scene, const KdTree& tree, const Layout& layout,
                   const RenderOptions& options)
    : scene_(scene), tree_(tree), options_(options), plan_(plan_ray_kinds(scene, options.max_depth)) {
  camera_ = options.camera ? *options.camera : scene.camera ? *scene.camera : default_camera(tree.bounds());
  if (options.fov_y_degrees) camera_.fov_y_degrees = *options.fov_y_degrees;
  const auto& slots = layout.slot_of_node;
  const auto& nodes = tree.nodes();
  if (slots.size() != nodes.size()) throw std::invalid_argument("layout does not match the kd-tree");
  node_records_.resize(nodes.size());
  compact_.resize(nodes.size());
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    const KdNode& n = nodes[i];
    node_records_[i] = {options.addresses.node_base + std::uint64_t{slots[i]} * options.addresses.node_size,
                        options.addresses.node_size, formats::AccessType::Read,
                        static_cast<formats::Tag>(n.level)};
    if (n.is_leaf()) {
      compact_[i].first = n.first;
      compact_[i].bits = (n.count << 2) | KdNode::kLeafAxis;
    } else {
      // Traversal finds the left child next to its parent (pre-order).
      if (n.left != i + 1) throw std::invalid_argument("kd-tree nodes are not in pre-order");
      compact_[i].split = n.split;
      compact_[i].bits = (n.right << 2) | n.axis;
    }
  }
  // NFF / SPD convention (which AFF inherits): each of N lights has
  // intensity 1 / sqrt(N). Pixels only; the rays cast do not depend on it.
  light_scale_ = scene.lights.size() > 1 ? 1.0f / std::sqrt(float(scene.lights.size())) : 1.0f;
  face_normals_.reserve(scene.triangles.size());
  for (const auto& t : scene.triangles) face_normals_.push_back(triangle_unit_normal(t, {0, 0, 1}));
}

template <bool AnyHit>
bool Renderer::traverse(const Ray& ray, float t_max, Hit& hit, std::vector<Record>* records,
                        RenderStats* stats) const {
  if (compact_.empty() || tree_.bounds().empty()) return false;
  // A ray with a non-finite or zero part meets nothing: without this its
  // NaN comparisons would send it to every node of the tree.
  const auto finite = [](const Vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); };
  if (!finite(ray.origin) || !finite(ray.direction) || ray.direction == Vec3{}) return false;
  const Vec3 inverse{1.0f / ray.direction.x, 1.0f / ray.direction.y, 1.0f / ray.direction.z};
  float t_min = 0, t_far = t_max;
  if (!intersect_box(tree_.bounds(), ray.origin, inverse, t_min, t_far)) return false;

  const detail::ShearedRay sheared(ray);
  const auto& primitives = tree_.primitives();
  const auto& streams = options_.streams;
  const auto& map = options_.addresses;
  const bool record_nodes = records && streams.nodes;
  struct Pending {
    std::uint32_t node;
    float t_min, t_max;
  };
  Pending stack[kMaxLevelLimit + 2];
  int top = 0;
  std::uint32_t node_index = 0;
  float best = t_max;
  bool found = false;
  std::uint64_t fetches = 0, leaves = 0, tests = 0;

  while (true) {
    const CompactNode node = compact_[node_index];
    ++fetches;
    if (record_nodes) records->push_back(node_records_[node_index]);
    const std::uint32_t axis = node.bits & 3u;
    if (axis != KdNode::kLeafAxis) {
      const float o = ray.origin[static_cast<int>(axis)];
      const float t_split = (node.split - o) * inverse[static_cast<int>(axis)];
      const bool below_first = o < node.split || (o == node.split && ray.direction[static_cast<int>(axis)] <= 0);
      const std::uint32_t left = node_index + 1, right = node.bits >> 2;
      const std::uint32_t first = below_first ? left : right;
      const std::uint32_t second = below_first ? right : left;
      if (t_split > t_far || t_split <= 0) {
        node_index = first;
      } else if (t_split < t_min) {
        node_index = second;
      } else {
        stack[top++] = {second, t_split, t_far};
        node_index = first;
        t_far = t_split;
      }
      continue;
    }
    ++leaves;
    const std::uint32_t count = node.bits >> 2;
    for (std::uint32_t i = 0; i < count; ++i) {
      const std::uint32_t slot = node.first + i;
      const std::uint32_t id = primitives[slot];
      if (records && streams.lists) {
        records->push_back({map.list_base + std::uint64_t{slot} * map.list_entry_size,
                            map.list_entry_size, formats::AccessType::Read,
                            formats::kTagPrimitiveList});
      }
      if (records && streams.triangles) {
        records->push_back({map.triangle_base + std::uint64_t{id} * map.triangle_size,
                            map.triangle_size, formats::AccessType::Read, formats::kTagTriangle});
      }
      ++tests;
      if (detail::intersect_sheared(sheared, scene_.triangles[id], best, hit)) {
        best = hit.t;
        hit.triangle = id;
        found = true;
        if constexpr (AnyHit) break;
      }
    }
    if constexpr (AnyHit) {
      if (found) break;
    }
    // The closest hit so far is final once it lies within this leaf's span;
    // a hit found past the span is kept (clipping rounding), not discarded.
    if (found && best <= t_far) break;
    if (top == 0) break;
    const Pending next = stack[--top];
    if (found && best < next.t_min) break;
    node_index = next.node;
    t_min = next.t_min;
    t_far = next.t_max;
  }
  if (stats) {
    stats->node_fetches += fetches;
    stats->leaf_visits += leaves;
    stats->triangle_tests += tests;
  }
  return found;
}

std::optional<Hit> Renderer::closest_hit(const Ray& ray, float t_max, std::vector<Record>* records,
                                         RenderStats* stats) const {
  Hit hit;
  if (traverse<false>(ray, t_max, hit, records, stats)) return hit;
  return std::nullopt;
}

bool Renderer::occluded(const Ray& ray, float t_max, std::vector<Record>* records,
                        RenderStats* stats) const {
  Hit hit;
  return traverse<true>(ray, t_max, hit, records, stats);
}

Vec3 Renderer::shade(const Ray& ray, RayKind kind, int depth, Context& context) const {
  ++context.stats.rays[static_cast<int>(kind)];
  const auto hit = closest_hit(ray, std::numeric_limits<float>::infinity(), context.records,
                               &context.stats);
  context.maybe_flush();
  if (!hit) return scene_.background;

  const Triangle& triangle = scene_.triangles[hit->triangle];
  static const Material kDefaultMaterial;
  const Material& material = triangle.material < scene_.materials.size()
                                 ? scene_.materials[triangle.material]
                                 : kDefaultMaterial;
  const float w = hit->b0;
  // The point from barycentrics lies on the surface more exactly than o + t d,
  // and its error is bounded by the vertices' magnitudes.
  const SurfacePoint surface = interpolate_surface_point(triangle, w, hit->u, hit->v);
  const Vec3& point = surface.point;
  const Vec3 face = face_normals_[hit->triangle];
  const bool entering = dot(ray.direction, face) < 0;
  const Vec3 facing = entering ? face : -face;  // geometric normal towards the incoming ray
  Vec3 normal = facing;
  if (scene_.vertex_normals.size() == scene_.triangles.size() * 3) {
    const Vec3* n = &scene_.vertex_normals[std::size_t{hit->triangle} * 3];
    const Vec3 smooth = n[0] * w + n[1] * hit->u + n[2] * hit->v;
    const float len = length(smooth);
    if (len > 0) normal = dot(smooth, facing) < 0 ? -smooth / len : smooth / len;
  }
  const Vec3 view = -normalize(ray.direction);

  Vec3 color = scene_.ambient * (material.ambient ? *material.ambient : material.diffuse);
  if (plan_.casts(RayKind::Shadow)) {
    const Vec3 shadow_origin = offset_ray_origin(surface, facing);
    for (const auto& light : scene_.lights) {
      const Vec3 to_light = light.position - point;
      // A light behind the surface lights nothing here: no ray is needed.
      if (dot(to_light, facing) <= 0) continue;
      ++context.stats.rays[static_cast<int>(RayKind::Shadow)];
      const Ray shadow{shadow_origin, light.position - shadow_origin};
      const bool blocked = occluded(shadow, 1.0f - 1e-4f, context.records, &context.stats);
      context.maybe_flush();
      if (blocked) continue;
      const Vec3 l = unit_vector(to_light);
      const float diffuse = std::max(0.0f, dot(normal, l));
      float specular = 0;
      if (material.shininess > 0 && (material.specular.x > 0 || material.specular.y > 0 ||
                                     material.specular.z > 0)) {
        specular = std::pow(std::max(0.0f, dot(reflect(-l, normal), view)), material.shininess);
      }
      color += light.color * light_scale_ * (material.diffuse * diffuse + material.specular * specular);
    }
  }
  if (depth >= options_.max_depth) return color;

  float reflect_weight = plan_.casts(RayKind::Reflection) ? material.reflectance : 0.0f;
  float refract_weight = 0;
  Vec3 refracted;
  if (plan_.casts(RayKind::Refraction) && material.transmittance > 0) {
    const float eta_i = entering ? 1.0f : material.ior, eta_t = entering ? material.ior : 1.0f;
    const float cos_i = std::clamp(dot(view, normal), 0.0f, 1.0f);
    const float eta = eta_i / eta_t;
    const float sin2_t = eta * eta * std::max(0.0f, 1.0f - cos_i * cos_i);
    if (sin2_t >= 1.0f) {
      reflect_weight += material.transmittance;  // total internal reflection
    } else {
      const float cos_t = std::sqrt(1.0f - sin2_t);
      const float fresnel = fresnel_dielectric(cos_i, cos_t, eta_i, eta_t);
      reflect_weight += material.transmittance * fresnel;
      refract_weight = material.transmittance * (1.0f - fresnel);
      refracted = normalize(-view * eta + normal * (eta * cos_i - cos_t));
    }
  }
  if (reflect_weight > 0 && plan_.casts(RayKind::Reflection)) {
    Vec3 direction = reflect(ray.direction, normal);
    // A smooth normal can send the mirror ray under the surface: use the face.
    if (dot(direction, facing) <= 0) direction = reflect(ray.direction, facing);
    const Ray reflection{offset_ray_origin(surface, facing), normalize(direction)};
    color += shade(reflection, RayKind::Reflection, depth + 1, context) * reflect_weight;
  }
  if (refract_weight > 0 && dot(refracted, facing) < 0) {
    const Ray refraction{offset_ray_origin(surface, -facing), refracted};
    color += shade(refraction, RayKind::Refraction, depth + 1, context) * refract_weight;
  }
  return color;
}

void Renderer::render_pixel(std::uint32_t pixel, Context& context, Image* image) const {
  const int x = static_cast<int>(pixel % static_cast<std::uint32_t>(options_.width));
  const int y = static_cast<int>(pixel / static_cast<std::uint32_t>(options_.width));
  const Vec3 forward = unit_vector(camera_.look_at - camera_.eye);
  Vec3 right = cross(forward, camera_.up);
  if (length(right) == 0) right = cross(forward, std::fabs(forward.y) < 0.9f ? Vec3{0, 1, 0} : Vec3{1, 0, 0});
  right = normalize(right);
  const Vec3 up = cross(right, forward);
  const float half_height = std::tan(camera_.fov_y_degrees * 0.5f * 3.14159265f / 180.0f);
  const float half_width = half_height * float(options_.width) / float(options_.height);
  const float sx = ((float(x) + 0.5f) / float(options_.width) * 2.0f - 1.0f) * half_width;
  const float sy = (1.0f - (float(y) + 0.5f) / float(options_.height) * 2.0f) * half_height;
  const Ray primary{camera_.eye, normalize(forward + right * sx + up * sy)};
  const Vec3 color = shade(primary, RayKind::Primary, 1, context);
  if (image) image->pixels[pixel] = color;
}

RenderStats Renderer::render(const RecordSink& sink, Image* image, const Progress& progress) const {
  const auto start = std::chrono::steady_clock::now();
  if (image) {
    image->width = options_.width;
    image->height = options_.height;
    image->pixels.assign(static_cast<std::size_t>(options_.width) * options_.height, Vec3{});
  }
  const auto sequence =
      pixel_sequence(options_.width, options_.height, options_.pixel_order, options_.tile_size);
  const std::size_t chunk_pixels = static_cast<std::size_t>(std::max(1, options_.pixels_per_chunk));
  const std::size_t chunks = (sequence.size() + chunk_pixels - 1) / chunk_pixels;
  unsigned threads = options_.threads ? options_.threads : std::thread::hardware_concurrency();
  threads = std::max(1u, std::min<unsigned>(threads, static_cast<unsigned>(std::max<std::size_t>(chunks, 1))));

  struct Chunk {
    std::vector<Record> records;
    RenderStats stats;
    std::uint64_t flushed = 0;
    bool done = false;
  };
  // Set up for threads below: waits until chunk c is the next to emit.
  std::function<void(std::size_t)> wait_for_turn;
  auto render_chunk = [&](std::size_t c, Chunk& chunk) {
    Context context;
    context.records = options_.record ? &chunk.records : nullptr;
    if (context.records) {
      context.flush_at = std::max<std::size_t>(1, options_.records_per_flush);
      context.flush = [&, c] {
        if (sink && wait_for_turn) wait_for_turn(c);
        context.flushed += chunk.records.size();
        if (sink) sink(chunk.records);
        chunk.records.clear();
      };
    }
    const std::size_t end = std::min(sequence.size(), (c + 1) * chunk_pixels);
    for (std::size_t i = c * chunk_pixels; i < end; ++i) render_pixel(sequence[i], context, image);
    chunk.stats = context.stats;
    chunk.flushed = context.flushed;
  };

  RenderStats total;
  auto emit = [&](std::size_t c, Chunk& chunk) {
    chunk.stats.records = chunk.flushed + chunk.records.size();
    chunk.flushed = 0;
    total += chunk.stats;
    if (options_.record && sink && !chunk.records.empty()) sink(chunk.records);
    chunk.records.clear();  // keeps the capacity: no page faults refilling it
    if (progress) progress(double(c + 1) / double(chunks));
  };

  if (threads <= 1) {
    Chunk chunk;
    for (std::size_t c = 0; c < chunks; ++c) {
      render_chunk(c, chunk);
      emit(c, chunk);
    }
  } else {
    // Workers render chunks ahead of the writer, at most `window` ahead; this
    // thread hands finished chunks to the sink strictly in order.
    const std::size_t window = std::size_t{threads} * 4;
    std::vector<Chunk> slots(window);
    std::mutex mutex;
    std::condition_variable changed;
    std::size_t next_chunk = 0, emitted = 0;
    bool failed = false;
    std::exception_ptr error;
    // A worker may hand its chunk's records on itself once every earlier
    // chunk is emitted: the writer is then waiting for this very chunk, so
    // the sink is never called from two threads at once.
    wait_for_turn = [&](std::size_t c) {
      std::unique_lock lock(mutex);
      changed.wait(lock, [&] { return failed || emitted == c; });
      if (failed) throw RenderCancelled{};
    };
    auto worker = [&] {
      while (true) {
        std::size_t c;
        {
          std::unique_lock lock(mutex);
          changed.wait(lock, [&] { return failed || next_chunk >= chunks || next_chunk < emitted + window; });
          if (failed || next_chunk >= chunks) return;
          c = next_chunk++;
        }
        Chunk& chunk = slots[c % window];
        try {
          render_chunk(c, chunk);
        } catch (const RenderCancelled&) {
          return;
        } catch (...) {
          std::lock_guard lock(mutex);
          failed = true;
          if (!error) error = std::current_exception();
          changed.notify_all();
          return;
        }
        std::lock_guard lock(mutex);
        chunk.done = true;
        changed.notify_all();
      }
    };
    std::vector<std::thread> pool;
    try {
      // Inside the try: if a thread cannot start, those started are told to
      // stop and joined (a joinable std::thread destroyed would terminate).
      for (unsigned t = 0; t < threads; ++t) {
        try {
          pool.emplace_back(worker);
        } catch (const std::system_error& e) {
          throw std::runtime_error("cannot start " + std::to_string(threads) + " threads (" + std::to_string(t) +
                                   " started): " + e.what());
        }
      }
      for (std::size_t c = 0; c < chunks; ++c) {
        Chunk& chunk = slots[c % window];
        {
          std::unique_lock lock(mutex);
          changed.wait(lock, [&] { return failed || chunk.done; });
          if (failed) break;
        }
        emit(c, chunk);
        std::lock_guard lock(mutex);
        chunk.done = false;
        ++emitted;
        changed.notify_all();
      }
    } catch (...) {
      std::lock_guard lock(mutex);
      failed = true;
      if (!error) error = std::current_exception();
      changed.notify_all();
    }
    for (auto& t : pool) t.join();
    if (error) std::rethrow_exception(error);
  }
  total.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return total;
}

}  // namespace nodetrace::tracer
