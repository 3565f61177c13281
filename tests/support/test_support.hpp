// Helpers shared by every test program: where ../shared and the built
// programs are, temporary directories, and running a command.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace nodetrace::testing {

// ../shared beside the checkout, or nullopt when it is absent.
std::optional<std::filesystem::path> shared_dir();

// True when absent shared data must fail the test instead of skipping it
// (NODETRACE_REQUIRE_SHARED=1, set by .ci/run).
bool shared_data_required();

// Path of a program built into build/bin.
std::filesystem::path program(const std::string& name);

// A fresh directory removed when the object goes out of scope.
class TempDir {
 public:
  TempDir();
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::string& name) const { return path_ / name; }

 private:
  std::filesystem::path path_;
};

struct CommandResult {
  int exit_code = -1;
  std::string out;  // standard output
  std::string err;  // standard error
};

// `path` single-quoted for /bin/sh (test paths hold no quote).
std::string shell_quoted(const std::filesystem::path& path);

// Names in `folder` that are output temporaries (the output rule's `.NAME.tmp-`).
std::vector<std::string> temporaries(const std::filesystem::path& folder);

// Runs `command` with /bin/sh, optionally feeding `input` on stdin.
CommandResult run_command(const std::string& command, const std::string& input = {});

// The real Dinero IV to compare against: $DINEROIV (a program path), else
// dineroIV on PATH, else the one scripts/build-dinero.sh built into
// build/dinero/. nullopt when there is none.
std::optional<std::filesystem::path> real_dinero();

// A BART AFF scene of two animation frames whose trees differ: a grid of
// grid x grid squares of triangles, one of them moving, written to
// folder/moving.aff; its path.
std::filesystem::path write_two_frame_scene(const std::filesystem::path& folder, int grid);

std::string read_file(const std::filesystem::path& path);
void write_file(const std::filesystem::path& path, const std::string& bytes);

// The rows of CSV text as a loader sees them (RFC 4180: quoted fields, doubled
// quotes); an empty line is a row of no cells, as Python's csv.reader gives it.
std::vector<std::vector<std::string>> csv_rows(const std::string& text);

// The rows after the header line of CSV text, each as column -> cell (empty
// lines skipped).
std::vector<std::map<std::string, std::string>> csv_table(const std::string& text);

// Empty when `text` is exactly one table: the header `columns` (or, when
// `columns` is empty, any header), then rows of its width; else what is wrong.
std::string one_csv_table(const std::string& text, const std::vector<std::string>& columns = {});

}  // namespace nodetrace::testing

// Binds `var` to the shared directory; skips the test with a message when it
// is absent, or fails it when shared data is required (CI).
#define NODETRACE_SHARED_OR_SKIP(var)                                              \
  const auto var##_optional = ::nodetrace::testing::shared_dir();                  \
  if (!var##_optional) {                                                           \
    if (::nodetrace::testing::shared_data_required()) {                            \
      FAIL() << "../shared is absent but NODETRACE_REQUIRE_SHARED=1";              \
    }                                                                              \
    GTEST_SKIP() << "../shared not found beside the checkout: golden test skipped"; \
  }                                                                                \
  const std::filesystem::path var = *var##_optional

// Binds `var` to the real Dinero IV (real_dinero()); skips the test with a
// message when there is none, or fails it when shared data is required (CI
// builds it from ../shared with scripts/build-dinero.sh).
#define NODETRACE_DINERO_OR_SKIP(var)                                                     \
  const auto var##_optional = ::nodetrace::testing::real_dinero();                        \
  if (!var##_optional) {                                                                  \
    if (::nodetrace::testing::shared_data_required()) {                                   \
      FAIL() << "no Dinero IV ($DINEROIV, PATH, build/dinero/dineroIV) but "               \
                "NODETRACE_REQUIRE_SHARED=1: run scripts/build-dinero.sh";                \
    }                                                                                     \
    GTEST_SKIP() << "no Dinero IV ($DINEROIV, PATH or build/dinero/dineroIV; "             \
                    "scripts/build-dinero.sh builds it): comparison skipped";             \
  }                                                                                       \
  const std::filesystem::path var = *var##_optional
