#include "test_support.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string_view>

namespace nodetrace::testing {

std::optional<std::filesystem::path> shared_dir() {
  std::filesystem::path dir = NODETRACE_SHARED_DIR;
  if (const char* env = std::getenv("NODETRACE_SHARED_DIR"); env && *env) dir = env;
  if (std::filesystem::is_directory(dir / "dinero-golden")) return dir;
  return std::nullopt;
}

bool shared_data_required() {
  const char* env = std::getenv("NODETRACE_REQUIRE_SHARED");
  return env && std::string(env) == "1";
}

std::filesystem::path program(const std::string& name) {
  return std::filesystem::path(NODETRACE_BIN_DIR) / name;
}

std::optional<std::filesystem::path> real_dinero() {
  namespace fs = std::filesystem;
  auto runnable = [](const fs::path& path) { return ::access(path.c_str(), X_OK) == 0 && fs::is_regular_file(path); };
  if (const char* env = std::getenv("DINEROIV"); env && *env) {
    if (runnable(env)) return fs::path(env);
  }
  if (const char* path = std::getenv("PATH")) {
    std::string_view rest = path;
    while (true) {
      const auto colon = rest.find(':');
      const std::string dir(rest.substr(0, colon));
      const fs::path candidate = fs::path(dir.empty() ? "." : dir) / "dineroIV";
      if (runnable(candidate)) return candidate;
      if (colon == std::string_view::npos) break;
      rest.remove_prefix(colon + 1);
    }
  }
  const fs::path built = fs::path(NODETRACE_SOURCE_DIR) / "build" / "dinero" / "dineroIV";
  if (runnable(built)) return built;
  return std::nullopt;
}

TempDir::TempDir() {
  std::random_device device;
  const auto base = std::filesystem::temp_directory_path();
  for (int attempt = 0; attempt < 100; ++attempt) {
    auto candidate = base / ("nodetrace-test-" + std::to_string(::getpid()) + "-" +
                             std::to_string(device()));
    if (std::filesystem::create_directory(candidate)) {
      path_ = candidate;
      return;
    }
  }
  throw std::runtime_error("cannot create a temporary directory");
}

TempDir::~TempDir() {
  std::error_code ignored;
  std::filesystem::remove_all(path_, ignored);
}

std::string shell_quoted(const std::filesystem::path& path) {
  std::string text = "'";
  text.append(path.string()).append("'");
  return text;
}

std::vector<std::string> temporaries(const std::filesystem::path& folder) {
  std::vector<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(folder)) {
    const std::string name = entry.path().filename().string();
    if (name.find(".tmp-") != std::string::npos) names.push_back(name);
  }
  return names;
}

CommandResult run_command(const std::string& command, const std::string& input) {
  TempDir dir;
  const auto in_path = dir / "stdin";
  const auto out_path = dir / "stdout";
  const auto err_path = dir / "stderr";
  write_file(in_path, input);
  const std::string full = "(" + command + ") <'" + in_path.string() + "' >'" +
                           out_path.string() + "' 2>'" + err_path.string() + "'";
  const int status = std::system(full.c_str());
  CommandResult result;
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  result.out = read_file(out_path);
  result.err = read_file(err_path);
  return result;
}

std::vector<std::map<std::string, std::string>> csv_table(const std::string& text) {
  const auto rows = csv_rows(text);
  std::vector<std::map<std::string, std::string>> out;
  for (std::size_t r = 1; r < rows.size(); ++r) {
    if (rows[r].empty()) continue;
    auto& row = out.emplace_back();
    for (std::size_t c = 0; c < rows[0].size() && c < rows[r].size(); ++c) row[rows[0][c]] = rows[r][c];
  }
  return out;
}

std::string read_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

std::vector<std::vector<std::string>> csv_rows(const std::string& text) {
  std::vector<std::vector<std::string>> rows;
  std::vector<std::string> row;
  std::string cell;
  bool quoted = false, any = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (quoted) {
      if (c == '"' && i + 1 < text.size() && text[i + 1] == '"') {
        cell += '"';
        ++i;
      } else if (c == '"') {
        quoted = false;
      } else {
        cell += c;
      }
    } else if (c == '"') {
      quoted = any = true;
    } else if (c == ',') {
      row.push_back(std::move(cell));
      cell.clear();
      any = true;
    } else if (c == '\n') {
      if (any || !cell.empty()) row.push_back(std::move(cell));
      cell.clear();
      rows.push_back(std::move(row));
      row.clear();
      any = false;
    } else if (c != '\r') {
      cell += c;
      any = true;
    }
  }
  if (any || !cell.empty()) {
    row.push_back(std::move(cell));
    rows.push_back(std::move(row));
  }
  return rows;
}

std::string one_csv_table(const std::string& text, const std::vector<std::string>& columns) {
  const auto rows = csv_rows(text);
  if (rows.empty()) return "no header";
  if (!columns.empty() && rows[0] != columns) {
    std::string header;
    for (const auto& cell : rows[0]) header += cell + ",";
    return "header is " + header;
  }
  for (std::size_t r = 1; r < rows.size(); ++r) {
    if (rows[r].size() != rows[0].size()) {
      return "row " + std::to_string(r + 1) + " has " + std::to_string(rows[r].size()) + " cells, the header " +
             std::to_string(rows[0].size());
    }
  }
  return {};
}

void write_file(const std::filesystem::path& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary);
  out << bytes;
}

std::filesystem::path write_two_frame_scene(const std::filesystem::path& folder, int grid) {
  std::string scene = "a 0 1 2\nx mover { p 3  0 0 0  1 0 0  0 1 0 }\nl 0 0 5\n";
  for (int i = 0; i < grid; ++i) {
    for (int j = 0; j < grid; ++j) {
      scene += "p 3  " + std::to_string(i) + " " + std::to_string(j) + " -2  " + std::to_string(i + 1) + " " +
               std::to_string(j) + " -2  " + std::to_string(i) + " " + std::to_string(j + 1) + " -1.5\n";
    }
  }
  scene += "k mover {\n transl 2\n 0  0 0 0  0 0 0\n 1  5 5 1  0 0 0\n}\n";
  const auto path = folder / "moving.aff";
  write_file(path, scene);
  return path;
}

}  // namespace nodetrace::testing
