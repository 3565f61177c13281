#include "nodetrace/tracer/render/image.hpp"

#include <png.h>

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <memory>

#include "nodetrace/base/error.hpp"
#include "nodetrace/base/output_file.hpp"
#include "nodetrace/base/portable_math.hpp"

namespace nodetrace::tracer {

namespace {

// Whitted colours are written as computed, clamped, with no gamma curve:
// scene files of the Whitted era (NFF, AFF) choose their colours for direct
// display. Linear radiance goes through the sRGB curve (portable pow: the
// same PNG on every machine).
std::uint8_t to_byte(float value, bool linear_radiance) {
  float v = std::clamp(value, 0.0f, 1.0f);  // NaN never reaches here: the path tracer drops it
  if (linear_radiance) {
    v = v <= 0.0031308f ? 12.92f * v : 1.055f * base::portable_math::pow(v, 1.0f / 2.4f) - 0.055f;
  }
  return static_cast<std::uint8_t>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f));
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
        row[3 * x] = to_byte(c.x, image.linear_radiance);
        row[3 * x + 1] = to_byte(c.y, image.linear_radiance);
        row[3 * x + 2] = to_byte(c.z, image.linear_radiance);
      }
      png_write_row(png, row.data());
    }
    png_write_end(png, nullptr);
  }
  png_destroy_write_struct(png ? &png : nullptr, info ? &info : nullptr);
  if (!ok) throw base::IoError(sink.error.empty() ? path + ": cannot write PNG" : sink.error);
  out.commit();
}

void write_pfm(const Image& image, const std::vector<Vec3>& plane, const std::string& path) {
  if (plane.size() != static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height)) {
    throw base::UsageError(path + ": the image has no such plane");
  }
  base::OutputFile out(path);
  // A negative scale says little-endian.
  out.write("PF\n" + std::to_string(image.width) + " " + std::to_string(image.height) + "\n-1.0\n");
  std::string row(static_cast<std::size_t>(image.width) * 12, '\0');
  for (int y = image.height - 1; y >= 0; --y) {
    for (int x = 0; x < image.width; ++x) {
      const Vec3& c = plane[static_cast<std::size_t>(y) * image.width + x];
      for (int k = 0; k < 3; ++k) {
        std::uint32_t bits;
        const float value = c[k];
        std::memcpy(&bits, &value, 4);
        for (int b = 0; b < 4; ++b) row[std::size_t(x) * 12 + std::size_t(k) * 4 + b] = char((bits >> (8 * b)) & 0xFF);
      }
    }
    out.write(row);
  }
  out.commit();
}

}  // namespace nodetrace::tracer

namespace nodetrace::tracer {

namespace {

// A header field: skips whitespace, then reads up to the next whitespace.
std::string pfm_token(const std::string& bytes, std::size_t& at) {
  while (at < bytes.size() && std::isspace(static_cast<unsigned char>(bytes[at]))) ++at;
  const std::size_t begin = at;
  while (at < bytes.size() && !std::isspace(static_cast<unsigned char>(bytes[at]))) ++at;
  return bytes.substr(begin, at - begin);
}

std::uint64_t pfm_size(const std::string& token, const std::string& path, const char* what) {
  if (token.empty() || token.size() > 9 || token.find_first_not_of("0123456789") != std::string::npos) {
    throw base::FormatError(fmt::format("{}: PFM header: expected the {} as a decimal number, got '{}'", path, what,
                                        token));
  }
  return std::stoull(token);
}

}  // namespace

Image read_pfm(const std::string& path, std::uint64_t max_pixels) {
  std::error_code error;
  if (std::filesystem::is_directory(path, error)) throw base::IoError(path + ": cannot read: it is a directory");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw base::IoError(fmt::format("{}: cannot read: {}", path, std::strerror(errno)));
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw base::IoError(path + ": cannot read");
  std::size_t at = 0;
  const std::string magic = pfm_token(bytes, at);
  if (magic == "Pf") {
    throw base::FormatError(path + ": a greyscale PFM ('Pf'): expected a colour PFM ('PF', three floats a pixel)");
  }
  if (magic != "PF") {
    throw base::FormatError(path + ": not a PFM file: expected 'PF' (a colour PFM) at the start");
  }
  const std::uint64_t width = pfm_size(pfm_token(bytes, at), path, "width");
  const std::uint64_t height = pfm_size(pfm_token(bytes, at), path, "height");
  const std::string scale_text = pfm_token(bytes, at);
  char* end = nullptr;
  const double scale = scale_text.empty() ? 0.0 : std::strtod(scale_text.c_str(), &end);
  if (scale_text.empty() || end != scale_text.c_str() + scale_text.size() || !std::isfinite(scale) || scale == 0) {
    throw base::FormatError(fmt::format("{}: PFM header: expected a nonzero scale (negative: little-endian), got '{}'",
                                        path, scale_text));
  }
  if (width == 0 || height == 0) {
    throw base::FormatError(fmt::format("{}: a PFM of {}x{} pixels: expected at least one pixel", path, width, height));
  }
  if (width * height > max_pixels) {
    throw base::FormatError(fmt::format("{}: a PFM of {}x{} pixels: at most {} pixels", path, width, height,
                                        max_pixels));
  }
  ++at;  // the one whitespace character after the scale
  const std::uint64_t expected = width * height * 12;
  const std::uint64_t available = at <= bytes.size() ? bytes.size() - at : 0;
  if (available != expected) {
    throw base::FormatError(fmt::format("{}: a PFM of {}x{} pixels needs {} bytes of pixels after its header: {} {}",
                                        path, width, height, expected, available,
                                        available < expected ? "(truncated)" : "(bytes after the last pixel)"));
  }
  const bool little_endian = scale < 0;
  Image image;
  image.width = static_cast<int>(width);
  image.height = static_cast<int>(height);
  image.pixels.resize(width * height);
  const auto* data = reinterpret_cast<const unsigned char*>(bytes.data() + at);
  for (std::uint64_t stored_row = 0; stored_row < height; ++stored_row) {
    Vec3* row = &image.pixels[(height - 1 - stored_row) * width];  // the file's first row is the bottom one
    for (std::uint64_t x = 0; x < width; ++x) {
      for (int k = 0; k < 3; ++k) {
        const unsigned char* b = data + ((stored_row * width + x) * 3 + std::uint64_t(k)) * 4;
        const std::uint32_t bits = little_endian ? std::uint32_t(b[0]) | std::uint32_t(b[1]) << 8 |
                                                       std::uint32_t(b[2]) << 16 | std::uint32_t(b[3]) << 24
                                                 : std::uint32_t(b[3]) | std::uint32_t(b[2]) << 8 |
                                                       std::uint32_t(b[1]) << 16 | std::uint32_t(b[0]) << 24;
        float value;
        std::memcpy(&value, &bits, 4);
        row[x][k] = value;
      }
    }
  }
  return image;
}

}  // namespace nodetrace::tracer
