#include "nodetrace/tracer/render/image.hpp"

#include <png.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>

#include "nodetrace/base/error.hpp"
#include "nodetrace/base/output_file.hpp"

namespace nodetrace::tracer {

namespace {

// Colours are written as computed, clamped, with no gamma curve: scene files of
// the Whitted era (NFF, AFF) choose their colours for direct display.
std::uint8_t to_byte(float value) {
  return static_cast<std::uint8_t>(std::lround(std::clamp(value, 0.0f, 1.0f) * 255.0f));
}

}  // namespace

void write_png(const Image& image, const std::string& path) {
  // The one output rule of every program: a temporary renamed into place for
  // a file, a device or FIFO written directly (formats/output_file.hpp).
  base::OutputFile out(path);
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  std::vector<std::uint8_t> row(static_cast<std::size_t>(image.width) * 3);
  struct Sink {
    base::OutputFile* out;
    std::string error;
  } sink{&out, {}};
  volatile bool ok = png && info;
  if (ok && setjmp(png_jmpbuf(png))) ok = false;
  if (ok) {
    png_set_write_fn(
        png, &sink,
        [](png_structp writing, png_bytep data, png_size_t length) {
          auto* target = static_cast<Sink*>(png_get_io_ptr(writing));
          try {
            target->out->write(std::string_view(reinterpret_cast<const char*>(data), length));
          } catch (const std::exception& error) {
            target->error = error.what();
          }
          // libpng's own error path (longjmp), taken outside the handler.
          if (!target->error.empty()) png_error(writing, "write failed");
        },
        [](png_structp) {});
    png_set_IHDR(png, info, static_cast<png_uint_32>(image.width),
                 static_cast<png_uint_32>(image.height), 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, info);
    for (int y = 0; y < image.height; ++y) {
      for (int x = 0; x < image.width; ++x) {
        const Vec3& c = image.pixels[static_cast<std::size_t>(y) * image.width + x];
        row[3 * x] = to_byte(c.x);
        row[3 * x + 1] = to_byte(c.y);
        row[3 * x + 2] = to_byte(c.z);
      }
      png_write_row(png, row.data());
    }
    png_write_end(png, nullptr);
  }
  png_destroy_write_struct(png ? &png : nullptr, info ? &info : nullptr);
  if (!ok) throw base::IoError(sink.error.empty() ? path + ": cannot write PNG" : sink.error);
  out.commit();
}

}  // namespace nodetrace::tracer
