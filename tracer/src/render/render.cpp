// The render loop: the pixel sequence cut into chunks, rendered on the
// workers of an ordered pipeline (formats/ordered_pipeline.hpp) ahead of the
// one thread that hands each chunk's records to the sink strictly in
// sequence order, so the records do not depend on the thread count.
#include "nodetrace/tracer/render/render.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <mutex>
#include <utility>
#include <thread>

#include "nodetrace/base/huge_pages.hpp"
#include "nodetrace/base/ordered_pipeline.hpp"
#include "nodetrace/tracer/render/interaction.hpp"
#include "render/ray_timing.hpp"
#include "render/emitters.hpp"
#include "render/render_context.hpp"

namespace nodetrace::tracer {

using formats::Record;

namespace {
// Unwinds a worker whose render was abandoned because another one failed.
struct RenderCancelled {};

Camera camera_to_use(const Scene& scene, const Bounds& bounds, const RenderOptions& options) {
  Camera camera = options.camera ? *options.camera : scene.camera ? *scene.camera : default_camera(bounds);
  if (options.fov_y_degrees) camera.fov_y_degrees = *options.fov_y_degrees;
  return camera;
}
}  // namespace

Renderer::Renderer(const Scene& scene, const KdTree& tree, const Layout& layout, const RenderOptions& options)
    : Renderer(scene, tree.bounds(), std::make_unique<Traversal>(scene.triangles, tree, layout, options.streams,
                                                                 options.addresses),
               options) {}

Renderer::Renderer(const Scene& scene, const AccelerationStructure& accel, const Layout& layout,
                   const RenderOptions& options)
    : Renderer(scene, accel.bounds(), accel.traversal(scene.triangles, layout, options.streams, options.addresses),
               options) {}

Renderer::Renderer(const Scene& scene, const Bounds& bounds, std::unique_ptr<RayTraversal> traversal,
                   const RenderOptions& options)
    : scene_(scene),
      options_(options),
      plan_(options.integrator == Integrator::Path ? plan_path_ray_kinds(scene, options.path.max_bounces,
                                                                         options.environment && options.environment->lights())
                                                   : plan_ray_kinds(scene, options.max_depth, options.rays)),
      camera_(camera_to_use(scene, bounds, options)),
      pinhole_(camera_, options.width, options.height),
      traversal_(std::move(traversal)) {
  // NFF / SPD convention (which AFF inherits): each of N lights has
  // intensity 1 / sqrt(N). Pixels only; the rays cast do not depend on it.
  lights_shadowed_ = options.first_light_only ? std::min<std::size_t>(1, scene.lights.size()) : scene.lights.size();
  light_scale_ = lights_shadowed_ > 1 ? 1.0f / std::sqrt(float(lights_shadowed_)) : 1.0f;
  face_normals_.reserve(scene.triangles.size());
  for (const auto& t : scene.triangles) face_normals_.push_back(triangle_unit_normal(t, {0, 0, 1}));
  if (options.integrator == Integrator::Path) emitters_ = std::make_shared<const detail::Emitters>(scene);
}

std::optional<Hit> Renderer::closest_hit(const Ray& ray, float t_max, std::vector<Record>* records,
                                         RenderStats* stats) const {
  Hit hit;
  if (traversal_->closest_hit(ray, t_max, hit, records, stats)) return hit;
  return std::nullopt;
}

bool Renderer::occluded(const Ray& ray, float t_max, std::vector<Record>* records,
                        RenderStats* stats) const {
  return traversal_->any_hit(ray, t_max, records, stats);
}

std::vector<Renderer::CastRay> Renderer::cast_rays(std::uint64_t begin, std::uint64_t end) const {
  const auto sequence = pixel_sequence(options_.width, options_.height, options_.pixel_order, options_.tile_size);
  std::vector<CastRay> rays;
  Context context;
  context.cast = &rays;
  for (std::uint64_t i = begin; i < std::min<std::uint64_t>(end, sequence.size()); ++i) {
    render_pixel(sequence[i], context, nullptr);
  }
  return rays;
}

RenderStats Renderer::render(const RecordCallback& sink, Image* image, const Progress& progress) const {
  if (options_.rays_in_flight > 1 || options_.units > 1) return render_in_flight(sink, image, progress);
  const PixelRun all{0, static_cast<std::uint64_t>(options_.width) * static_cast<std::uint64_t>(options_.height)};
  return render_runs({&all, 1}, {}, sink, image, progress);
}

RenderStats Renderer::render_runs(std::span<const PixelRun> runs, const RunStart& run_start, const RecordCallback& sink,
                                  Image* image, const Progress& progress) const {
  const auto start = std::chrono::steady_clock::now();
  if (image) prepare_image(*image);
  const auto sequence =
      pixel_sequence(options_.width, options_.height, options_.pixel_order, options_.tile_size);
  const std::size_t chunk_pixels = static_cast<std::size_t>(std::max(1, options_.pixels_per_chunk));
  // Chunks of each run; none spans two runs, so a run starts with a chunk.
  struct ChunkSpan {
    std::size_t begin, end, run;
  };
  std::vector<ChunkSpan> spans;
  for (std::size_t r = 0; r < runs.size(); ++r) {
    const std::size_t end = std::min<std::size_t>(sequence.size(), runs[r].end);
    for (std::size_t b = runs[r].begin; b < end; b += chunk_pixels) spans.push_back({b, std::min(end, b + chunk_pixels), r});
  }
  const std::size_t chunks = spans.size();
  // Runs announced so far; only the thread whose turn it is to hand records
  // on touches it, so the announcements are in order.
  std::size_t runs_started = 0;
  const auto start_runs_through = [&](std::size_t run) {
    for (; runs_started <= run && runs_started < runs.size(); ++runs_started) {
      if (run_start) run_start(runs_started);
    }
  };
  unsigned threads = options_.threads ? options_.threads : std::thread::hardware_concurrency();
  threads = std::max(1u, std::min<unsigned>(threads, static_cast<unsigned>(std::max<std::size_t>(chunks, 1))));

  struct Chunk {
    std::vector<Record> records;
    RenderStats stats;
    std::uint64_t flushed = 0;
  };
  // Set up for threads below: waits until chunk c is the next to emit.
  std::function<void(std::size_t)> wait_for_turn;
  auto render_chunk = [&](std::size_t c, Chunk& chunk) {
    Context context;
    context.records = options_.record ? &chunk.records : nullptr;
    if (context.records) {
      context.flush_at = std::max<std::size_t>(1, options_.records_per_flush);
      // A buffer's first use: a flush's worth, before it is touched.
      if (chunk.records.capacity() == 0) base::reserve_on_huge_pages(chunk.records, context.flush_at);
      context.flush = [&, c] {
        if (sink) {
          if (wait_for_turn) wait_for_turn(c);
          start_runs_through(spans[c].run);  // it is this chunk's turn: no other thread is here
        }
        context.flushed += chunk.records.size();
        if (sink) sink(chunk.records);
        chunk.records.clear();
      };
    }
    const double cpu_start = detail::thread_cpu_seconds();
    for (std::size_t i = spans[c].begin; i < spans[c].end; ++i) render_pixel(sequence[i], context, image);
    context.stats.cpu_seconds = detail::thread_cpu_seconds() - cpu_start;
    chunk.stats = context.stats;
    chunk.flushed = context.flushed;
  };

  RenderStats total;
  auto emit = [&](std::size_t c, Chunk& chunk) {
    chunk.stats.records = chunk.flushed + chunk.records.size();
    chunk.flushed = 0;
    total += chunk.stats;
    start_runs_through(spans[c].run);
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
    // Workers render chunks ahead of this thread, at most `window` ahead; the
    // pipeline hands the finished chunks back strictly in order.
    const std::size_t window = std::size_t{threads} * 4;
    // A worker may hand its chunk's records on itself when its chunk is the
    // one this thread is waiting for (`turn`), so the sink is never called
    // from two threads at once. Such a worker waits for earlier chunks only,
    // which are running or done: the pipeline's queue starts jobs in the
    // order they were submitted.
    std::mutex mutex;
    std::condition_variable changed;
    std::size_t turn = 0;
    bool cancelled = false;
    std::vector<std::vector<Record>> spare;  // emptied record buffers, kept for their capacity
    wait_for_turn = [&](std::size_t c) {
      std::unique_lock lock(mutex);
      changed.wait(lock, [&] { return cancelled || turn == c; });
      if (cancelled) throw RenderCancelled{};
    };
    base::OrderedPipeline<Chunk> pipeline(threads);
    // Destroyed before the pipeline: on the way out (an exception from the
    // sink or a job), workers waiting for a turn that will not come stop, so
    // the pipeline's destructor can wait for them.
    struct CancelOnExit {
      std::mutex& mutex;
      std::condition_variable& changed;
      bool& cancelled;
      ~CancelOnExit() {
        {
          std::lock_guard lock(mutex);
          cancelled = true;
        }
        changed.notify_all();
      }
    } cancel_on_exit{mutex, changed, cancelled};
    std::size_t submitted = 0;
    for (std::size_t c = 0; c < chunks; ++c) {
      for (; submitted < chunks && submitted < c + window; ++submitted) {
        pipeline.submit([&, s = submitted] {
          Chunk chunk;
          {
            std::lock_guard lock(mutex);
            if (cancelled) return chunk;  // the render failed: nobody will take it
            if (!spare.empty()) {
              chunk.records = std::move(spare.back());
              spare.pop_back();
            }
          }
          render_chunk(s, chunk);
          return chunk;
        });
      }
      {
        std::lock_guard lock(mutex);
        turn = c;
      }
      changed.notify_all();
      Chunk chunk = pipeline.pop();
      emit(c, chunk);
      std::lock_guard lock(mutex);
      spare.push_back(std::move(chunk.records));
    }
  }
  if (!runs.empty()) start_runs_through(runs.size() - 1);  // runs without a pixel
  total.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return total;
}

}  // namespace nodetrace::tracer
