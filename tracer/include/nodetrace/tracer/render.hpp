// The Whitted renderer: pinhole primary rays, shadow rays to the lights,
// mirror reflection and refraction (Snell, Fresnel, total internal
// reflection), over a kd-tree stored in a given layout. Every traversal
// records the node fetches it makes (DESIGN.md "What a traversal fetches").
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "nodetrace/formats/record.hpp"
#include "nodetrace/tracer/image.hpp"
#include "nodetrace/tracer/kdtree.hpp"
#include "nodetrace/tracer/layout.hpp"
#include "nodetrace/tracer/scene.hpp"

namespace nodetrace::tracer {

enum class PixelOrder : std::uint8_t { Scanline, Tiled, Morton };
std::string_view pixel_order_name(PixelOrder order);
std::optional<PixelOrder> parse_pixel_order(std::string_view name);

// Pixel indices (y * width + x) in the order they are rendered. Tiled: tiles
// of tile_size x tile_size in scanline order, scanline inside each. Morton:
// Z-order over the image.
std::vector<std::uint32_t> pixel_sequence(int width, int height, PixelOrder order, int tile_size);

enum class RayKind : std::uint8_t { Primary = 0, Shadow = 1, Reflection = 2, Refraction = 3 };
inline constexpr int kRayKindCount = 4;
std::string_view ray_kind_name(RayKind kind);

// Which ray kinds a scene needs; the others are never cast, and `why_not`
// says why (e.g. "no light").
struct RayKindPlan {
  std::array<bool, kRayKindCount> cast{};
  std::array<std::string, kRayKindCount> why_not;
  bool casts(RayKind kind) const { return cast[static_cast<int>(kind)]; }
};
RayKindPlan plan_ray_kinds(const Scene& scene, int max_depth);

// Which records a traversal writes: node fetches (tag = level), leaf
// primitive-list reads (tag p), triangle reads (tag t).
struct StreamSelection {
  bool nodes = true, lists = false, triangles = false;
};

struct AddressMap {
  std::uint64_t node_base = 0;
  std::uint32_t node_size = 8;
  std::uint64_t list_base = 0x40000000;  // 4-byte triangle indices of leaves
  std::uint32_t list_entry_size = 4;
  std::uint64_t triangle_base = 0x80000000;  // three vertices of 3 floats each
  std::uint32_t triangle_size = 36;
};

struct RenderOptions {
  int width = 800, height = 600;
  int max_depth = 10;  // primary rays are depth 1; no secondary ray beyond it
  PixelOrder pixel_order = PixelOrder::Scanline;
  int tile_size = 8;
  std::optional<Camera> camera;  // overrides the scene's camera
  std::optional<float> fov_y_degrees;  // overrides the field of view of the camera used
  unsigned threads = 0;          // 0: one per core
  bool record = true;            // false: render only (no records made)
  StreamSelection streams;
  AddressMap addresses;
  int pixels_per_chunk = 512;  // unit of parallel work (does not change the output)
  // A chunk's records go to the sink once this many are waiting, even in the
  // middle of a pixel, so memory does not grow with the ray tree (does not
  // change the output; a sink call may hold one traversal more).
  std::size_t records_per_flush = std::size_t{1} << 18;
};

struct RenderStats {
  std::array<std::uint64_t, kRayKindCount> rays{};
  std::uint64_t node_fetches = 0;    // node visits
  std::uint64_t leaf_visits = 0;     // leaves among them
  std::uint64_t triangle_tests = 0;  // ray/triangle tests
  std::uint64_t records = 0;         // records handed to the sink
  double seconds = 0;                // wall time of render()
  std::uint64_t total_rays() const { return rays[0] + rays[1] + rays[2] + rays[3]; }
  RenderStats& operator+=(const RenderStats& other);
};

struct Ray {
  Vec3 origin, direction;
};

struct Hit {
  float t = 0;
  std::uint32_t triangle = 0;
  float u = 0, v = 0;  // barycentrics of v1 and v2
  float b0 = 0;        // barycentric of v0, from its own edge function (not 1 - u - v)
};

// A camera that frames `bounds` from the front, slightly above and right.
Camera default_camera(const Bounds& bounds);

// Watertight ray/triangle test (Woop, Benthin and Wald 2013): hits with
// 0 < t < t_max, where t is also beyond its own rounding error. A ray exactly
// through an edge shared by two triangles hits exactly one of them, and one
// through the shared vertex of a closed fan exactly one of the fan. New rays
// start at offset_ray_origin (interaction.hpp).
std::optional<Hit> intersect_triangle(const Ray& ray, const Triangle& triangle, float t_max);

class Renderer {
 public:
  using RecordSink = std::function<void(std::span<const formats::Record>)>;
  using Progress = std::function<void(double fraction_done)>;

  // Keeps references to all three; they must outlive the renderer.
  Renderer(const Scene& scene, const KdTree& tree, const Layout& layout,
           const RenderOptions& options);

  // Renders every pixel. Records reach `sink` in the sequential order (pixel
  // by pixel, each pixel's ray tree depth-first) whatever the thread count.
  // `image` (optional) receives the picture.
  RenderStats render(const RecordSink& sink, Image* image, const Progress& progress = {}) const;

  // One traversal each, appending its records to `records` when not null.
  std::optional<Hit> closest_hit(const Ray& ray, float t_max, std::vector<formats::Record>* records,
                                 RenderStats* stats) const;
  bool occluded(const Ray& ray, float t_max, std::vector<formats::Record>* records,
                RenderStats* stats) const;

  const RayKindPlan& ray_plan() const { return plan_; }
  const Camera& camera() const { return camera_; }

 private:
  struct Context;
  template <bool AnyHit>
  bool traverse(const Ray& ray, float t_max, Hit& hit, std::vector<formats::Record>* records,
                RenderStats* stats) const;
  Vec3 shade(const Ray& ray, RayKind kind, int depth, Context& context) const;
  void render_pixel(std::uint32_t pixel, Context& context, Image* image) const;

  const Scene& scene_;
  const KdTree& tree_;
  RenderOptions options_;
  RayKindPlan plan_;
  Camera camera_;
  // What traversal reads of a node, 8 bytes: interior nodes keep the split
  // and (right child << 2 | axis), the left child being next in pre-order;
  // leaves keep the first primitive and (count << 2 | 3).
  struct CompactNode {
    union {
      float split;
      std::uint32_t first;
    };
    std::uint32_t bits;
  };
  std::vector<CompactNode> compact_;
  std::vector<formats::Record> node_records_;  // the fetch record of each node
  std::vector<Vec3> face_normals_;           // unit geometric normals
  float light_scale_ = 1;
};

}  // namespace nodetrace::tracer
