#include "render/trace_header.hpp"

#include <fmt/format.h>

#include <charconv>
#include <cstdlib>
#include <string>

#include "nodetrace/formats/container/metadata.hpp"
#include "render/emitters.hpp"
#include "render/ggx.hpp"
#include "render/path_lobes.hpp"
#include "render/path_random.hpp"

namespace nodetrace::tracer {

namespace {

// A float as the double with the same shortest decimal form (0.2f -> 0.2, not
// 0.20000000298023224), so headers read as they were typed.
double shortest(float value) {
  char text[32];
  const auto [end, error] = std::to_chars(text, text + sizeof text, value);
  (void)error;
  return std::strtod(std::string(text, end).c_str(), nullptr);
}

// Everything that decides a path tracer's rays, in words where a reader needs them.
nlohmann::json path_tracing_description(const PathOptions& path) {
  nlohmann::json description = {{"integrator", "path"},
          {"spp", path.samples_per_pixel},
          {"max_bounces", path.max_bounces},
          {"roulette", fmt::format("before every bounce ray from bounce {} on: survives with probability min({}, "
                                   "largest throughput component), divided by it",
                                   kRouletteFromBounce, shortest(kMaxSurvival))},
          {"lobes", "one per bounce, chosen with probability proportional to mean Kd (diffuse, cosine-weighted), "
                    "mean Ks when shininess > 0 (glossy, modified Phong), reflectance (mirror), transmittance "
                    "(dielectric: Fresnel chooses reflection or refraction); the chosen lobe's weight is divided "
                    "by that probability"},
          {"light", "one shadow ray per point light in front of the surface (next-event estimation); the "
                    "background is light from every direction a path escapes in; the ambient term is added at "
                    "every hit, as the Whitted tracer adds it"},
          {"camera", "one ray per sample through a uniformly random point of the pixel"},
          {"random", fmt::format("Philox4x32-10, counter (pixel, sample, bounce << 16 | dimension / 4, frame & "
                                 "0xffffffff), key ({:#x}, frame >> 32)",
                                 detail::kPathSeed ^ path.seed)},
          {"nonfinite", "a sample whose throughput or radiance becomes NaN or infinite ends, counts as black, and "
                        "is counted in the trailer's totals (nonfinite_samples)"}};
  // Written only for the Sobol sampler, so the independent one's headers are as before.
  if (path.sampler == PathSampler::Sobol) {
    description["sampler"] = fmt::format(
        "sobol: per pixel and pair of dimensions, the sample number permuted (Kensler 2013) by a hash, indexing "
        "Sobol dimensions 0 and 1, Owen-scrambled (Burley 2020) by hashes; the hashes are Philox4x32-10 of "
        "(pixel, bounce, first dimension of the pair, frame & 0xffffffff), key ({:#x}, frame >> 32)",
        detail::kSobolSeed ^ path.seed);
  }
  // Written only when given, so the headers of renders without it are as before.
  if (path.seed != 0) description["seed"] = fmt::format("--path-seed {}: XORed into the keys above", path.seed);
  return description;
}

// Some triangle's material has a GGX lobe.
bool has_ggx_lobe(const Scene& scene) {
  for (const Triangle& t : scene.triangles) {
    if (t.material < scene.materials.size() && detail::lobe_weights(scene.materials[t.material]).ggx > 0) return true;
  }
  return false;
}

// What a GGX lobe is and how the integrator lights it.
std::string ggx_description(Integrator integrator) {
  const std::string lobe = fmt::format(
      "GGX microfacet lobes (OBJ Pr with Ks, AFF fg): Blender Cycles' Glossy BSDF with distribution GGX, "
      "alpha = max(roughness^2, {}), GGX D, separable Smith G = G1(v) G1(l), no Fresnel term, BRDF x cos = "
      "colour D G / (4 cos_v)",
      shortest(detail::kMinGgxAlpha));
  if (integrator == Integrator::Whitted) {
    return lobe + "; they reflect the point lights only (pi x BRDF x cos, the lights' convention), no rays of their own";
  }
  return lobe + "; one bounce chooses one with probability proportional to its mean colour and draws a visible "
                "normal (Heitz 2018) from random dimensions 1 and 2, weight colour x G1(l); lit by next-event "
                "estimation as a diffuse lobe is, combined per lobe with the bounce ray by the power heuristic";
}

// The map as the user named it, its size and checksum, and how it lights.
nlohmann::json environment_description(const EnvironmentMap& map) {
  return {{"file", map.name()},
          {"width", map.width()},
          {"height", map.height()},
          {"checksum", map.checksum()},
          {"mapping", "equirectangular, Blender's with no axis conversion: u = 0.5 - atan2(y, x) / (2 pi), v = 0.5 + "
                      "atan2(z, hypot(x, y)) / pi; the nearest pixel, column floor(u width), row floor(v height) "
                      "from the bottom (+Z the top row, +X the middle column, +Y a quarter from the left)"},
          {"light", fmt::format(
                        "replaces the background: rays that escape collect the map's radiance; at each diffuse or "
                        "glossy hit one more shadow ray, unbounded, goes in a direction drawn {}, random dimensions "
                        "8 and 9 of the next bounce; combined per lobe with the bounce ray by the power heuristic",
                        map.sampling() == EnvironmentSampling::Uniform
                            ? "uniformly over the sphere"
                            : "by luminance x solid angle (a row by its pixels' luminance times its band of the "
                              "sphere, a column by luminance, a direction uniform within the pixel)")}};
}

}  // namespace

nlohmann::json make_trace_header(const SceneSource& source, const Scene& first_scene,
                           const TraceJobOptions& options, const LayoutTrace& target, std::uint32_t split_level,
                           const RayKindPlan& plan, std::uint64_t frame_count, int depth_limit) {
  const RenderOptions& r = options.render;
  nlohmann::json header;
  header["producer"] = {{"tool", "tracer"}, {"version", NODETRACE_VERSION}};
  header["scene"] = {{"name", source.name()},
                     {"hash", source.content_hash()},
                     {"triangles", first_scene.triangles.size()}};
  // Written only when the scene has light its file does not give.
  if (!first_scene.default_light.empty()) header["scene"]["default_light"] = first_scene.default_light;
  // A path's rays form a chain of max_bounces + 1 (primary rays are depth 1).
  const int max_depth = r.integrator == Integrator::Path ? r.path.max_bounces + 1 : r.max_depth;
  nlohmann::json render = {{"width", r.width},
                           {"height", r.height},
                           {"max_depth", max_depth},
                           {"pixel_order", pixel_order_name(r.pixel_order)},
                           {"frames", frame_count},
                           {"first_frame", options.frames.first}};
  if (options.frames.step != 1) render["frame_step"] = options.frames.step;
  if (r.pixel_order == PixelOrder::Tiled) render["tile_size"] = r.tile_size;
  if (options.time) render["time"] = *options.time;
  if (r.camera) {
    const Camera& c = *r.camera;
    render["camera"] = {{"eye", {shortest(c.eye.x), shortest(c.eye.y), shortest(c.eye.z)}},
                        {"look_at", {shortest(c.look_at.x), shortest(c.look_at.y), shortest(c.look_at.z)}},
                        {"up", {shortest(c.up.x), shortest(c.up.y), shortest(c.up.z)}},
                        // The fov the rays use: --fov overrides the camera's (render.cpp camera_to_use).
                        {"fov", shortest(r.fov_y_degrees.value_or(c.fov_y_degrees))}};
  }
  if (r.fov_y_degrees) render["fov"] = shortest(*r.fov_y_degrees);
  // Written only for a scene with a GGX lobe, so other headers are as before.
  if (has_ggx_lobe(first_scene)) render["ggx"] = ggx_description(r.integrator);
  // Written only when narrowed, so a default render's header is as before.
  if (r.rays != RayScope::Whitted) render["rays"] = ray_scope_name(r.rays);
  if (r.first_light_only) render["lights"] = "first";
  // Written only with rays in flight, so a sequential render's header is as
  // before; the writer adds the top-level "units" the readers go by.
  if (r.rays_in_flight > 1 || r.units > 1) {
    render["rays_in_flight"] = r.rays_in_flight;
    render["units"] = r.units;
    render["unit_pixels"] = r.unit_pixels;
    render["ready_order"] = ready_order_name(r.ready_order);
  }
  // Written only for path tracing, so a Whitted render's header is as before.
  if (r.integrator == Integrator::Path) {
    render["path"] = path_tracing_description(r.path);
    // Written only for a scene with emitters, so other headers are as before.
    if (!detail::Emitters(first_scene).empty()) {
      render["path"]["emitters"] =
          "emissive triangles (OBJ Ke, AFF fe) are two-sided area lights: rays that meet one collect its "
          "radiance; at each diffuse or glossy hit one more shadow ray goes to a point uniform on an emitter "
          "chosen by power (area x mean radiance), random dimensions 5 and 6 of the next bounce (the first, rescaled "
          "within the chosen emitter's share, also places the point); the two estimates "
          "are combined per lobe with the power heuristic";
    }
    // Written only with --environment, so other headers are as before.
    if (r.environment) render["path"]["environment"] = environment_description(*r.environment);
  }
  header["render"] = render;
  nlohmann::json layout = {{"name", layout_name(target.layout)},
                           {"node_size", r.addresses.node_size},
                           {"node_base", r.addresses.node_base}};
  // Only the hybrid layout has a BFL top part: a split level written for the
  // others would make simulators compare their K against a meaningless 0.
  if (target.layout == LayoutKind::Hybrid) {
    layout["split_level"] = split_level;
    if (target.high_size) layout["high_size"] = *target.high_size;
  }
  if (target.layout == LayoutKind::Treelet) layout["treelet_bytes"] = options.treelet_bytes;
  header["layout"] = layout;
  if (options.accel == AccelKind::KdTree) {
    // No "accel" key: a kd-tree trace keeps the bytes it had before BVHs.
    header["kdtree"] = {{"traversal_cost", shortest(options.build.traversal_cost)},
                        {"intersection_cost", shortest(options.build.intersection_cost)},
                        {"empty_bonus", shortest(options.build.empty_bonus)},
                        {"max_depth", depth_limit}};
    // The default limit depends on each frame's triangle count: say so, since
    // max_depth is then the first frame's.
    if (options.build.max_depth == 0) header["kdtree"]["max_depth_default"] = "8 + 1.3 log2 triangles, per frame";
    if (options.build.leaf_size) header["kdtree"]["leaf_size"] = options.build.leaf_size;
  } else {
    const unsigned arity = accel_arity(options.accel);
    nlohmann::json accel = {{"name", accel_name(options.accel)},
                            {"arity", arity},
                            {"node_size", r.addresses.node_size},
                            {"stored_node_size", default_node_size(options.accel)},
                            {"record", "one per node fetched, the whole node, tagged with its level"}};
    accel["node"] = options.accel == AccelKind::CwBvh8
                        ? "8 child boxes quantized to 8 bits per plane on a power-of-two grid (conservative), "
                          "child references"
                        : fmt::format("{} full-precision child boxes and child references", arity);
    if (arity > 2) accel["collapse"] = "binary BVH opened greedily: the interior child of largest surface area first";
    header["accel"] = accel;
    header["bvh"] = {{"build", "binned SAH"},
                     {"bins", options.bvh.bins},
                     {"traversal_cost", shortest(options.bvh.traversal_cost)},
                     {"intersection_cost", shortest(options.bvh.intersection_cost)},
                     {"max_leaf_size", options.bvh.max_leaf_size}};
  }
  nlohmann::json cast = nlohmann::json::array();
  nlohmann::json left_out = nlohmann::json::object();
  for (const RayKind kind : plan.kinds) {
    const std::string name(ray_kind_name(kind));
    if (plan.casts(kind)) {
      cast.push_back(name);
    } else {
      left_out[name] = plan.why_not[static_cast<int>(kind)];
    }
  }
  header["rays"] = {{"cast", cast}, {"left_out", left_out}};
  // A light behind the surface lights nothing there, so it gets no ray.
  if (plan.casts(RayKind::Shadow)) {
    std::string shadow = r.first_light_only ? "one to the first light when in front of the surface hit"
                                            : "one per light in front of the surface hit";
    if (r.integrator == Integrator::Path) shadow += ", at hits on a material with a diffuse or glossy lobe";
    header["rays"]["shadow"] = shadow;
  }
  nlohmann::json streams = nlohmann::json::array();
  if (r.streams.nodes) streams.push_back("nodes");
  if (r.streams.lists) streams.push_back("lists");
  if (r.streams.triangles) streams.push_back("triangles");
  header["streams"] = {{"kinds", streams}};
  if (r.streams.lists) {
    header["streams"]["list_base"] = r.addresses.list_base;
    header["streams"]["list_entry_size"] = r.addresses.list_entry_size;
  }
  if (r.streams.triangles) {
    header["streams"]["triangle_base"] = r.addresses.triangle_base;
    header["streams"]["triangle_size"] = r.addresses.triangle_size;
  }
  if (options.sampling) {
    const RowSampling& sampling = *options.sampling;
    formats::SamplingInfo info;
    info.method = "rows";
    info.every = sampling.every;
    info.band_height = sampling.band_height;
    info.seed = sampling.seed;
    info.bands = band_count(r.height, sampling.band_height);
    // A band is a run of band_height x width positions of the pixel sequence
    // (row_sampling.hpp): whole rows in scanline order.
    info.extra = {{"band_pixels", std::uint64_t(sampling.band_height) * std::uint64_t(r.width)}};
    header["sampling"] = info.to_json();
  }
  return header;
}

}  // namespace nodetrace::tracer
