// docs/ARCHITECTURE.md's folder map against the tree: every folder it names
// exists, and every folder holding C++ sources is named, so the map a
// newcomer reads is the tree they find.
#include <gtest/gtest.h>

#include <filesystem>
#include <regex>
#include <set>
#include <string>

#include "test_support.hpp"

namespace fs = std::filesystem;
using nodetrace::testing::read_file;

namespace {

const fs::path kSource = NODETRACE_SOURCE_DIR;

// The backquoted folder names (ending in '/') of the "Folder map" section.
std::set<std::string> mapped_folders() {
  const std::string text = read_file(kSource / "docs" / "ARCHITECTURE.md");
  const std::size_t begin = text.find("\n## Folder map\n");
  EXPECT_NE(begin, std::string::npos) << "docs/ARCHITECTURE.md has no \"## Folder map\" section";
  if (begin == std::string::npos) return {};
  const std::size_t end = text.find("\n## ", begin + 1);
  const std::string section = text.substr(begin, end == std::string::npos ? std::string::npos : end - begin);
  std::set<std::string> folders;
  static const std::regex folder("`([A-Za-z0-9_./-]+/)`");
  for (auto it = std::sregex_iterator(section.begin(), section.end(), folder); it != std::sregex_iterator(); ++it) {
    folders.insert((*it)[1].str());
  }
  return folders;
}

// Folders (relative, with a trailing '/') of the components and tests that hold .cpp or .hpp files.
std::set<std::string> source_folders() {
  std::set<std::string> folders;
  for (const char* top : {"base", "cli", "formats", "tracer", "cachesim", "tests"}) {
    for (const auto& entry : fs::recursive_directory_iterator(kSource / top)) {
      const std::string extension = entry.path().extension().string();
      if (!entry.is_regular_file() || (extension != ".cpp" && extension != ".hpp")) continue;
      folders.insert(entry.path().parent_path().lexically_relative(kSource).generic_string() + "/");
    }
  }
  return folders;
}

}  // namespace

TEST(ArchitectureMap, EveryFolderItNamesExists) {
  const std::set<std::string> mapped = mapped_folders();
  ASSERT_GT(mapped.size(), 20u) << "the folder map names too few folders to be the map";
  for (const std::string& folder : mapped) {
    EXPECT_TRUE(fs::is_directory(kSource / folder)) << "docs/ARCHITECTURE.md names " << folder
                                                    << ", which is not a folder of the tree";
  }
}

TEST(ArchitectureMap, EverySourceFolderIsNamed) {
  const std::set<std::string> mapped = mapped_folders();
  const std::set<std::string> sources = source_folders();
  ASSERT_FALSE(sources.empty());
  for (const std::string& folder : sources) {
    EXPECT_TRUE(mapped.count(folder)) << folder << " holds C++ sources but docs/ARCHITECTURE.md's folder map "
                                      << "does not name it";
  }
}
