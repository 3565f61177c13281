// The render loop with rays in flight (Renderer::render_in_flight): the
// pixel sequence cut into chunks traced on the workers of an ordered
// pipeline, each pixel's rays kept apart (PixelRays), and one RayScheduler on
// this thread interleaving them in chunk order, so the records do not depend
// on the thread count. Memory: the chunks traced ahead (a few per thread),
// plus the pixels the scheduler holds (those with a ray in a slot or in a
// queue, and those dealt to a unit that lags the others).
#include <algorithm>
#include <chrono>
#include <thread>

#include "nodetrace/base/ordered_pipeline.hpp"
#include "nodetrace/tracer/render/render.hpp"
#include "render/render_context.hpp"

namespace nodetrace::tracer {

using formats::Record;

RenderStats Renderer::render_in_flight(const RecordCallback& sink, Image* image, const Progress& progress) const {
  const auto start = std::chrono::steady_clock::now();
  if (image) {
    image->width = options_.width;
    image->height = options_.height;
    image->pixels.assign(static_cast<std::size_t>(options_.width) * options_.height, Vec3{});
  }
  const auto sequence = pixel_sequence(options_.width, options_.height, options_.pixel_order, options_.tile_size);
  const std::size_t chunk_pixels = static_cast<std::size_t>(std::max(1, options_.pixels_per_chunk));
  const std::size_t chunks = (sequence.size() + chunk_pixels - 1) / chunk_pixels;
  const std::uint64_t unit_pixels = std::max(1u, options_.unit_pixels);
  RayScheduler scheduler(options_.units, options_.rays_in_flight, options_.ready_order);

  struct Chunk {
    std::vector<PixelRays> pixels;
    RenderStats stats;
  };
  auto trace_chunk = [&](std::size_t c) {
    Chunk chunk;
    Context context;
    const std::size_t begin = c * chunk_pixels, end = std::min(sequence.size(), begin + chunk_pixels);
    chunk.pixels.resize(options_.record ? end - begin : 0);
    std::size_t last_records = 0, last_rays = 0;
    for (std::size_t i = begin; i < end; ++i) {
      if (options_.record) {
        // Neighbours cast similar ray trees: room for the last pixel's and a
        // quarter more saves most of the regrowth.
        PixelRays& pixel = chunk.pixels[i - begin];
        pixel.records.reserve(last_records + last_records / 4);
        pixel.rays.reserve(last_rays + last_rays / 4);
        context.records = &pixel.records;
        context.rays = &pixel.rays;
      }
      render_pixel(sequence[i], context, image);
      if (options_.record) {
        last_records = chunk.pixels[i - begin].records.size();
        last_rays = chunk.pixels[i - begin].rays.size();
      }
    }
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
    const std::size_t begin = c * chunk_pixels;
    for (std::size_t i = 0; i < chunk.pixels.size(); ++i) {
      const auto unit = static_cast<unsigned>(((begin + i) / unit_pixels) % options_.units);
      scheduler.add_pixel(unit, std::move(chunk.pixels[i]));
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
