// The progress line of long runs: one line on standard error, rewritten in
// place at most every 250 ms, shown only when standard error is a terminal
// (and the user did not ask for quiet), erased when the run ends.
#pragma once

#include <chrono>
#include <string>

namespace nodetrace::cli {

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
  // Erases the line (also done on destruction).
  void clear();

 private:
  bool shown_ = false;
  bool written_ = false;
  std::chrono::steady_clock::time_point last_{};
};

}  // namespace nodetrace::cli
