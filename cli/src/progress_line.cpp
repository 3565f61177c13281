#include "nodetrace/cli/progress_line.hpp"

#include <unistd.h>

#include <fmt/format.h>

#include <cmath>
#include <cstdio>

namespace nodetrace::cli {

namespace {

std::string count_text(double count) {
  return count >= 1e6 ? fmt::format("{:.1f} M", count / 1e6) : fmt::format("{:.0f}", count);
}

std::string duration_text(double seconds) {
  const auto whole = static_cast<std::uint64_t>(std::ceil(seconds));
  if (whole < 60) return fmt::format("{} s", whole);
  if (whole < 3600) return fmt::format("{}:{:02} min", whole / 60, whole % 60);
  return fmt::format("{}:{:02}:{:02} h", whole / 3600, whole / 60 % 60, whole % 60);
}

}  // namespace

std::string progress_text(std::string_view what, std::uint64_t done, std::optional<std::uint64_t> total,
                          std::string_view unit, double elapsed_seconds) {
  std::string text = fmt::format("{}: {}", what, count_text(static_cast<double>(done)));
  if (total && *total > 0) {
    text += fmt::format(" of {} {} ({}%)", count_text(static_cast<double>(*total)), unit,
                        std::min<std::uint64_t>(100, done * 100 / *total));
  } else {
    text += fmt::format(" {}", unit);
  }
  if (elapsed_seconds <= 0 || done == 0) return text;
  const double rate = static_cast<double>(done) / elapsed_seconds;
  text += fmt::format(", {} {}/s", count_text(rate), unit);
  // An estimate from the first moments (a tree still building, caches
  // cold) is mostly noise: none until enough work has been timed.
  const bool enough = elapsed_seconds >= kMinEstimateSeconds &&
                      static_cast<double>(done) >= kMinEstimateFraction * static_cast<double>(total.value_or(0));
  if (total && *total > done && enough) {
    text += fmt::format(", {} left", duration_text(static_cast<double>(*total - done) / rate));
  }
  return text;
}

void ProgressLine::update_count(std::string_view what, std::uint64_t done, std::optional<std::uint64_t> total,
                                std::string_view unit) {
  if (!shown_) return;
  const std::chrono::duration<double> elapsed = std::chrono::steady_clock::now() - start_;
  update(progress_text(what, done, total, unit, elapsed.count()));
}

ProgressLine::ProgressLine(bool wanted) : shown_(wanted && ::isatty(STDERR_FILENO) != 0) {}

ProgressLine::~ProgressLine() { clear(); }

void ProgressLine::update(const std::string& text) {
  if (!shown_) return;
  const auto now = std::chrono::steady_clock::now();
  if (written_ && now - last_ < std::chrono::milliseconds(250)) return;
  last_ = now;
  written_ = true;
  std::fprintf(stderr, "\r\033[K%s", text.c_str());
  std::fflush(stderr);
}

void ProgressLine::clear() {
  if (!written_) return;
  written_ = false;
  std::fputs("\r\033[K", stderr);
  std::fflush(stderr);
}

}  // namespace nodetrace::cli
