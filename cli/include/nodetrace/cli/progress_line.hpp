// The progress line of long runs: one line on standard error, rewritten in
// place at most every 250 ms, shown only when standard error is a terminal
// (and the user did not ask for quiet), erased when the run ends.
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace nodetrace::cli {

// The time left is estimated once this much time has passed and this
// fraction of the total is done, not before.
inline constexpr double kMinEstimateSeconds = 1.0;
inline constexpr double kMinEstimateFraction = 0.05;

// "WHAT: DONE of TOTAL UNIT (P%), RATE UNIT/s, T left" when the total is
// known, else "WHAT: DONE UNIT, RATE UNIT/s"; counts of a million and more in
// M with one decimal; no rate before any time has passed, and no time left
// before kMinEstimateSeconds and kMinEstimateFraction.
std::string progress_text(std::string_view what, std::uint64_t done, std::optional<std::uint64_t> total,
                          std::string_view unit, double elapsed_seconds);

class ProgressLine {
 public:
  // Shown when `wanted` and standard error is a terminal.
  explicit ProgressLine(bool wanted = true);
  ~ProgressLine();
  ProgressLine(const ProgressLine&) = delete;
  ProgressLine& operator=(const ProgressLine&) = delete;

  bool shown() const { return shown_; }
  // Replaces the line with `text` unless it was rewritten less than 250 ms ago.
  void update(const std::string& text);
  // progress_text of a count, timed from the last restart() (or construction).
  void update_count(std::string_view what, std::uint64_t done, std::optional<std::uint64_t> total,
                    std::string_view unit);
  // Starts timing a new run of counts (the next trace, say).
  void restart() { start_ = std::chrono::steady_clock::now(); }
  // Erases the line (also done on destruction).
  void clear();

 private:
  bool shown_ = false;
  bool written_ = false;
  std::chrono::steady_clock::time_point last_{};
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

}  // namespace nodetrace::cli
