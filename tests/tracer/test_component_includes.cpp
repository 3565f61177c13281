// The components meet only through their public include/ folders
// (DESIGN.md): the tracer program (tracer/tools) takes cachesim's simulation
// API from cachesim/include, never a header of cachesim/tools or
// cachesim/src, and the tracer library includes no cachesim at all.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

const fs::path kSource = NODETRACE_SOURCE_DIR;

struct Include {
  fs::path file;
  std::string header;
};

// The quoted includes (#include "...") of every source under `folder`.
std::vector<Include> quoted_includes(const fs::path& folder) {
  static const std::regex include(R"re(^\s*#\s*include\s*"([^"]+)")re");
  std::vector<Include> includes;
  for (const auto& entry : fs::recursive_directory_iterator(folder)) {
    const std::string extension = entry.path().extension().string();
    if (extension != ".cpp" && extension != ".hpp") continue;
    std::ifstream in(entry.path());
    std::string line;
    std::smatch match;
    while (std::getline(in, line)) {
      if (std::regex_search(line, match, include)) includes.push_back({entry.path(), match[1].str()});
    }
  }
  return includes;
}

// The folders of the libraries' public headers.
const std::vector<fs::path>& public_include_folders() {
  static const std::vector<fs::path> folders = {kSource / "base/include", kSource / "cli/include",
                                                kSource / "formats/include", kSource / "tracer/include",
                                                kSource / "tracer/options/include",
                                                kSource / "tracer/simulate/include",
                                                kSource / "cachesim/include"};
  return folders;
}

// Every quoted include under `folder` is beside the including file or in a
// library's public include/ folder.
void expect_only_own_and_public_headers(const fs::path& folder) {
  const std::vector<Include> includes = quoted_includes(folder);
  ASSERT_FALSE(includes.empty());
  for (const Include& include : includes) {
    // A quoted include resolves beside the including file first.
    if (fs::exists(include.file.parent_path() / include.header)) continue;
    bool in_public = false;
    for (const fs::path& folder : public_include_folders()) in_public = in_public || fs::exists(folder / include.header);
    std::string hidden_in;
    for (const char* hidden : {"cachesim/tools", "cachesim/src", "tracer/src", "formats/src"}) {
      if (fs::exists(kSource / hidden / include.header)) hidden_in = hidden;
    }
    EXPECT_TRUE(in_public) << include.file << ": \"" << include.header
                           << "\" is neither beside it nor in a library's include/ folder"
                           << (hidden_in.empty() ? "" : " (it is a header of " + hidden_in + ")");
  }
}

TEST(ComponentIncludes, TracerProgramIncludesOnlyItsOwnAndPublicHeaders) {
  expect_only_own_and_public_headers(kSource / "tracer/tools");
}

// The in-render simulation joins the tracer and cachesim through their
// public headers; the Python module binds the libraries the same way.
TEST(ComponentIncludes, InRenderSimulationAndPythonModuleIncludeOnlyPublicHeaders) {
  expect_only_own_and_public_headers(kSource / "tracer/simulate");
  expect_only_own_and_public_headers(kSource / "python/src");
}

TEST(ComponentIncludes, TracerLibraryIncludesNoCachesim) {
  for (const char* folder : {"tracer/src", "tracer/include"}) {
    for (const Include& include : quoted_includes(kSource / folder)) {
      EXPECT_EQ(include.header.find("cachesim"), std::string::npos) << include.file << ": \"" << include.header
                                                                     << "\"";
    }
  }
}

}  // namespace
