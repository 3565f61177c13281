// The render loop with rays in flight (Renderer::render_in_flight): the
// pixel sequence cut into chunks traced on the workers of an ordered
// pipeline, each pixel's rays kept apart (PixelRays; path tracing: each
// sample's, so a pixel's samples are independent trees), and one RayScheduler on
// this thread interleaving them in chunk order, so the records do not depend
// on the thread count. Memory: the chunks traced ahead (a few per thread),
// plus the pixels the scheduler holds (those with a ray in a slot or in a
// queue, and those dealt to a unit that lags the others).
#include <algorithm>
#include <chrono>
#include <thread>

#include "nodetrace/base/ordered_pipeline.hpp"
#include "nodetrace/tracer/render/render.hpp"
#include "render/ray_timing.hpp"
#include "render/render_context.hpp"

namespace nodetrace::tracer {

using formats::Record;

RenderStats Renderer::render_in_flight(const RecordCallback& sink, Image* image, const Progress& progress) const {
  const auto start = std::chrono::steady_clock::now();
  if (image) prepare_image(*image);
  const auto sequence = pixel_sequence(options_.width, options_.height, options_.pixel_order, options_.tile_size);
  const std::size_t chunk_pixels = static_cast<std::size_t>(std::max(1, options_.pixels_per_chunk));
  const std::size_t chunks = (sequence.size() + chunk_pixels - 1) / chunk_pixels;
  const std::uint64_t unit_pixels = std::max(1u, options_.unit_pixels);
  RayScheduler scheduler(options_.units, options_.rays_in_flight, options_.ready_order);

  // A chunk's ray trees in pixel-sequence order: one per sample of each
  // pixel (Whitted: one per pixel), each with its pixel's position.
  struct Chunk {
    std::vector<PixelRays> trees;
    std::vector<std::uint64_t> positions;
    RenderStats stats;
  };
  const std::size_t samples =
      options_.integrator == Integrator::Path ? options_.path.samples_per_pixel : std::size_t{1};
  auto trace_chunk = [&](std::size_t c) {
    Chunk chunk;
    Context context;
    const std::size_t begin = c * chunk_pixels, end = std::min(sequence.size(), begin + chunk_pixels);
    std::size_t position = begin;
    if (options_.record) {
      chunk.trees.reserve((end - begin) * samples);
      chunk.positions.reserve((end - begin) * samples);
      context.begin_sample = [&] {
        // Neighbours cast similar ray trees: room for the last tree's and a
        // quarter more saves most of the regrowth.
        const std::size_t last_records = chunk.trees.empty() ? 0 : chunk.trees.back().records.size();
        const std::size_t last_rays = chunk.trees.empty() ? 0 : chunk.trees.back().rays.size();
        PixelRays& tree = chunk.trees.emplace_back();
        tree.records.reserve(last_records + last_records / 4);
        tree.rays.reserve(last_rays + last_rays / 4);
        chunk.positions.push_back(position);
        context.records = &tree.records;
        context.rays = &tree.rays;
      };
    }
    const double cpu_start = detail::thread_cpu_seconds();
    for (; position < end; ++position) render_pixel(sequence[position], context, image);
    context.stats.cpu_seconds = detail::thread_cpu_seconds() - cpu_start;
    chunk.stats = context.stats;
    return chunk;
  };

  RenderStats total;
  std::vector<Record> out;
  auto hand_on = [&](bool all) {
    if (!out.empty() && (all || out.size() >= options_.records_per_flush)) {
      total.records += out.size();
      if (sink) sink(out);
      out.clear();
    }
  };
  auto schedule = [&](std::size_t c, Chunk& chunk) {
    total += chunk.stats;
    for (std::size_t i = 0; i < chunk.trees.size(); ++i) {
      const auto unit = static_cast<unsigned>((chunk.positions[i] / unit_pixels) % options_.units);
      scheduler.add_pixel(unit, std::move(chunk.trees[i]));
      // Run as far as the pixels so far allow, so the scheduler holds few.
      scheduler.run(out, false);
      hand_on(false);
    }
    if (progress) progress(double(c + 1) / double(chunks));
  };

  unsigned threads = base::threads_or_cores(options_.threads);
  threads = std::max(1u, std::min<unsigned>(threads, static_cast<unsigned>(std::max<std::size_t>(chunks, 1))));
  if (threads <= 1) {
    for (std::size_t c = 0; c < chunks; ++c) {
      Chunk chunk = trace_chunk(c);
      schedule(c, chunk);
    }
  } else {
    // Workers trace chunks at most `window` ahead of the scheduler.
    const std::size_t window = std::size_t{threads} * 2;
    base::OrderedPipeline<Chunk> pipeline(threads);
    std::size_t submitted = 0;
    for (std::size_t c = 0; c < chunks; ++c) {
      for (; submitted < chunks && submitted < c + window; ++submitted) {
        pipeline.submit([&, s = submitted] { return trace_chunk(s); });
      }
      Chunk chunk = pipeline.pop();
      schedule(c, chunk);
    }
  }
  scheduler.run(out, true);
  hand_on(true);
  total.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return total;
}

}  // namespace nodetrace::tracer
