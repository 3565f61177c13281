#include "nodetrace/cli/distinct_outputs.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <fmt/format.h>

#include <filesystem>
#include <optional>
#include <variant>

#include "nodetrace/base/error.hpp"
#include "nodetrace/base/output_file.hpp"

namespace nodetrace::cli {

namespace {

namespace fs = std::filesystem;

struct Inode {
  dev_t device;
  ino_t inode;
  bool operator==(const Inode&) const = default;
};
struct CharacterDevice {
  bool operator==(const CharacterDevice&) const { return false; }  // takes every output
};
// What a path reaches: an existing file, a character device, or a name yet
// to be created (resolved).
using FileIdentity = std::variant<Inode, CharacterDevice, std::string>;

FileIdentity identity_of(const struct stat& info) {
  if (S_ISCHR(info.st_mode)) return CharacterDevice{};
  return Inode{info.st_dev, info.st_ino};
}

FileIdentity identity(const std::string& path) {
  struct stat info {};
  if (path == "-") {
    if (::fstat(STDOUT_FILENO, &info) == 0) return identity_of(info);
    return std::string("-");
  }
  if (::stat(path.c_str(), &info) == 0) return identity_of(info);
  // A new name, or a link to one: the file the output rule would create.
  std::string target = path;
  try {
    target = base::plan_output(path).target;
  } catch (const base::IoError&) {
    // Not writable at all: the output's own check says why.
  }
  std::error_code error;
  const fs::path resolved = fs::weakly_canonical(fs::absolute(target, error), error);
  return error ? target : resolved.lexically_normal().string();
}

}  // namespace

bool same_output_file(const std::string& a, const std::string& b) {
  if (a == "-" && b == "-") return true;  // one stream, whatever it is
  return identity(a) == identity(b);
}

void check_distinct_outputs(const std::vector<NamedOutput>& outputs) {
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    if (outputs[i].path.empty()) continue;
    for (std::size_t j = 0; j < i; ++j) {
      if (outputs[j].path.empty() || !same_output_file(outputs[j].path, outputs[i].path)) continue;
      const NamedOutput& first = outputs[j];
      const NamedOutput& second = outputs[i];
      const std::string spelled =
          first.path == second.path ? fmt::format("'{}'", first.path)
                                    : fmt::format("'{}' and '{}'", first.path, second.path);
      const std::string both =
          first.option == second.option
              ? fmt::format("{} names the same file twice ({}), for two outputs", first.option, spelled)
          : first.path == second.path
              ? fmt::format("{} and {} both name '{}'{}", first.option, second.option, first.path,
                            first.path == "-" ? " (standard output)" : "")
              : fmt::format("{} '{}' and {} '{}' name one file", first.option, first.path, second.option,
                            second.path);
      throw base::UsageError(both + ": one output each; write one of them to another file");
    }
  }
}

}  // namespace nodetrace::cli
