// Child processes for dinero-wrap: posix_spawnp with stdin on a pipe and the
// output in unlinked temporary files (so a child can never block on a full
// output pipe while we block writing its input).
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fmt/format.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>

#include "nodetrace/cachesim/wrap/wrap.hpp"

extern char** environ;

namespace nodetrace::cachesim::wrap {

namespace {

int temporary_file() {
  std::string pattern = (std::filesystem::temp_directory_path() / "dinero-wrap-XXXXXX").string();
  const int fd = ::mkostemp(pattern.data(), O_CLOEXEC);
  if (fd < 0) throw WrapError(fmt::format("cannot create a temporary file: {}", std::strerror(errno)));
  ::unlink(pattern.c_str());
  return fd;
}

std::string read_all(int fd) {
  std::string text;
  ::lseek(fd, 0, SEEK_SET);
  char buffer[65536];
  while (true) {
    const ssize_t got = ::read(fd, buffer, sizeof buffer);
    if (got < 0 && errno == EINTR) continue;
    if (got <= 0) break;
    text.append(buffer, static_cast<std::size_t>(got));
  }
  return text;
}

void close_fd(int& fd) {
  if (fd >= 0) ::close(fd);
  fd = -1;
}

}  // namespace

ChildProcess::ChildProcess(const std::vector<std::string>& argv, Output output) {
  if (argv.empty()) throw WrapError("empty Dinero IV command");
  for (const auto& word : argv) {
    if (!command_.empty()) command_ += ' ';
    command_ += word;
  }
  int pipe_fds[2];
  if (::pipe2(pipe_fds, O_CLOEXEC) != 0) {
    throw WrapError(fmt::format("cannot create a pipe: {}", std::strerror(errno)));
  }
  stdin_fd_ = pipe_fds[1];
  // A larger pipe lets each child run ahead while we feed the others.
  ::fcntl(stdin_fd_, F_SETPIPE_SZ, 1 << 20);
  stdout_fd_ = temporary_file();
  if (output == Output::Captured) stderr_fd_ = temporary_file();
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, pipe_fds[0], 0);
  posix_spawn_file_actions_adddup2(&actions, stdout_fd_, 1);
  if (stderr_fd_ >= 0) posix_spawn_file_actions_adddup2(&actions, stderr_fd_, 2);
  // The child gets default SIGPIPE handling back even though we ignore it.
  posix_spawnattr_t attributes;
  posix_spawnattr_init(&attributes);
  sigset_t default_signals;
  sigemptyset(&default_signals);
  sigaddset(&default_signals, SIGPIPE);
  posix_spawnattr_setsigdefault(&attributes, &default_signals);
  posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETSIGDEF);
  std::vector<char*> args;
  for (const auto& word : argv) args.push_back(const_cast<char*>(word.c_str()));
  args.push_back(nullptr);
  pid_t pid = -1;
  const int error = ::posix_spawnp(&pid, args[0], &actions, &attributes, args.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  posix_spawnattr_destroy(&attributes);
  ::close(pipe_fds[0]);
  if (error != 0) {
    close_fd(stdin_fd_);
    close_fd(stdout_fd_);
    close_fd(stderr_fd_);
    throw WrapError(fmt::format("cannot run Dinero IV command '{}': {}", command_,
                                std::strerror(error)));
  }
  pid_ = pid;
}

ChildProcess::~ChildProcess() {
  close_fd(stdin_fd_);
  if (pid_ > 0) {
    ::kill(pid_, SIGTERM);
    int status = 0;
    while (::waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
    }
  }
  close_fd(stdout_fd_);
  close_fd(stderr_fd_);
}

bool ChildProcess::write(std::string_view bytes) {
  if (stdin_fd_ < 0) return false;
  while (!bytes.empty()) {
    const ssize_t written = ::write(stdin_fd_, bytes.data(), bytes.size());
    if (written < 0) {
      if (errno == EINTR) continue;
      const int error = errno;
      close_fd(stdin_fd_);
      if (error == EPIPE) return false;
      throw WrapError(fmt::format("cannot write to Dinero IV ('{}'): {}", command_, std::strerror(error)));
    }
    bytes.remove_prefix(static_cast<std::size_t>(written));
  }
  return true;
}

int ChildProcess::wait() {
  close_fd(stdin_fd_);
  if (pid_ <= 0) return -1;
  int status = 0;
  while (::waitpid(pid_, &status, 0) < 0) {
    if (errno != EINTR) break;
  }
  pid_ = -1;
  if (stdout_fd_ >= 0) output_ = read_all(stdout_fd_);
  if (stderr_fd_ >= 0) errors_ = read_all(stderr_fd_);
  close_fd(stdout_fd_);
  close_fd(stderr_fd_);
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
  return -1;
}

}  // namespace nodetrace::cachesim::wrap
