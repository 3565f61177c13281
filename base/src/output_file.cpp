#include "nodetrace/base/output_file.hpp"

#include <fcntl.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <fmt/format.h>

#include <array>
#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <random>

#include "nodetrace/base/error.hpp"

namespace nodetrace::base {

namespace {

namespace fs = std::filesystem;

constexpr int kMaxLinkHops = 40;  // as the kernel's own limit (ELOOP)
constexpr std::array<int, 4> kCleanupSignals = {SIGINT, SIGTERM, SIGHUP, SIGPIPE};

// Temporaries the signal handler removes. A fixed table of plain bytes, so
// the handler touches nothing but atomics and unlink(2).
constexpr int kSlots = 64;
constexpr std::size_t kSlotPathBytes = 4096;
struct Slot {
  std::atomic<bool> claimed{false};
  std::atomic<bool> live{false};
  char path[kSlotPathBytes];
};
Slot g_slots[kSlots];
// Set by the first cleanup signal: a temporary created from then on (by a
// thread the signal did not stop) is removed by its creator.
std::atomic<bool> g_dying{false};

// Every thread that takes a cleanup signal removes the temporaries before it
// restores the default action: had the first one reset it on delivery
// (SA_RESETHAND), a second signal (`timeout` sends two, a user may press
// Ctrl-C twice) would kill the process on another thread while the first
// was still removing them. The handler stays installed, so each signal
// runs it; removing a removed file again is harmless.
extern "C" void remove_temporaries_and_die(int signal_number) {
  g_dying.store(true);
  for (Slot& slot : g_slots) {
    if (slot.live.load()) ::unlink(slot.path);
  }
  struct sigaction action {};
  action.sa_handler = SIG_DFL;
  sigemptyset(&action.sa_mask);
  ::sigaction(signal_number, &action, nullptr);
  // The signal is blocked while this handler runs, so it takes effect as
  // soon as the handler returns.
  ::raise(signal_number);
}

// Installs the handler for the signals whose action is still the default;
// a program that ignores or handles one itself keeps its choice.
void install_cleanup_handler() {
  static std::once_flag once;
  std::call_once(once, [] {
    for (const int signal_number : kCleanupSignals) {
      struct sigaction old {};
      if (::sigaction(signal_number, nullptr, &old) != 0) continue;
      if ((old.sa_flags & SA_SIGINFO) != 0 || old.sa_handler != SIG_DFL) continue;
      struct sigaction action {};
      action.sa_handler = remove_temporaries_and_die;
      sigemptyset(&action.sa_mask);
      for (const int other : kCleanupSignals) sigaddset(&action.sa_mask, other);
      ::sigaction(signal_number, &action, nullptr);
    }
  });
}

int claim_slot(const std::string& path) {
  if (path.size() >= kSlotPathBytes) return -1;  // still removed on failure, not on a signal
  for (int i = 0; i < kSlots; ++i) {
    bool expected = false;
    if (g_slots[i].claimed.compare_exchange_strong(expected, true)) {
      std::memcpy(g_slots[i].path, path.c_str(), path.size() + 1);
      g_slots[i].live.store(true);
      return i;
    }
  }
  return -1;
}

void release_slot(int slot) {
  if (slot < 0) return;
  g_slots[slot].live.store(false, std::memory_order_release);
  g_slots[slot].claimed.store(false, std::memory_order_release);
}

// /dev/fd/N, /proc/self/fd/N, /proc/PID/fd/N (this process): descriptor N.
int named_descriptor(const std::string& path) {
  const std::string own = fmt::format("/proc/{}/fd/", ::getpid());
  for (const std::string& prefix : {std::string("/dev/fd/"), std::string("/proc/self/fd/"), own}) {
    if (path.size() <= prefix.size() || path.compare(0, prefix.size(), prefix) != 0) continue;
    const std::string digits = path.substr(prefix.size());
    if (digits.size() > 9 || digits.find_first_not_of("0123456789") != std::string::npos) return -1;
    return std::stoi(digits);
  }
  if (path == "/dev/stdout") return 1;
  if (path == "/dev/stderr") return 2;
  return -1;
}

std::string errno_text(int error) { return std::strerror(error); }

fs::path folder_of(const fs::path& target) { return target.has_parent_path() ? target.parent_path() : fs::path("."); }

}  // namespace

OutputPlan plan_output(const std::string& path) {
  OutputPlan plan;
  if (path == "-") {
    plan.method = OutputMethod::StandardOutput;
    plan.target = "-";
    return plan;
  }
  const auto fail = [&](const std::string& reason) -> OutputPlan {
    throw IoError(fmt::format("{}: cannot write: {}", path, reason));
  };
  if (path.empty()) return fail("the output name is empty");
  fs::path current = path;
  for (int hops = 0;; ++hops) {
    const int descriptor = named_descriptor(current.string());
    if (descriptor >= 0) {
      if (::fcntl(descriptor, F_GETFD) < 0) return fail(fmt::format("descriptor {} is not open", descriptor));
      plan.method = OutputMethod::Direct;
      plan.target = current.string();
      plan.descriptor = descriptor;
      return plan;
    }
    struct stat info {};
    if (::lstat(current.c_str(), &info) != 0) {
      if (errno != ENOENT) return fail(errno_text(errno));
      plan.method = OutputMethod::Replace;  // a new name
      plan.target = current.string();
      return plan;
    }
    if (S_ISLNK(info.st_mode)) {
      if (hops == kMaxLinkHops) return fail(errno_text(ELOOP));
      std::error_code error;
      const fs::path link = fs::read_symlink(current, error);
      if (error) return fail(error.message());
      current = link.is_absolute() ? link : folder_of(current) / link;
      continue;
    }
    if (S_ISDIR(info.st_mode)) return fail("is a directory");
    plan.target = current.string();
    plan.method = S_ISREG(info.st_mode) ? OutputMethod::Replace : OutputMethod::Direct;
    plan.socket = S_ISSOCK(info.st_mode);
    return plan;
  }
}

std::string temporary_prefix(const std::string& target) {
  const fs::path path(target);
  return (folder_of(path) / fmt::format(".{}.tmp-{}-", path.filename().string(), ::getpid())).string();
}

unsigned remove_stale_temporaries(const std::string& target) {
  const fs::path path(target);
  const std::string prefix = fmt::format(".{}.tmp-", path.filename().string());
  unsigned removed = 0;
  std::error_code error;
  for (fs::directory_iterator it(folder_of(path), error), end; !error && it != end; it.increment(error)) {
    const std::string name = it->path().filename().string();
    if (name.size() <= prefix.size() || name.compare(0, prefix.size(), prefix) != 0) continue;
    const std::size_t dash = name.find('-', prefix.size());
    const std::string digits = name.substr(prefix.size(), dash == std::string::npos ? 0 : dash - prefix.size());
    if (digits.empty() || digits.size() > 9 || digits.find_first_not_of("0123456789") != std::string::npos) continue;
    const pid_t owner = static_cast<pid_t>(std::stol(digits));
    if (owner == ::getpid() || ::kill(owner, 0) == 0 || errno != ESRCH) continue;  // its writer still runs
    if (::unlink(it->path().c_str()) == 0) ++removed;
  }
  return removed;
}

void check_output_writable(const std::string& path) {
  if (plan_output(path).method != OutputMethod::Replace) return;
  OutputFile probe(path);
  probe.abandon();
}

OutputFile::OutputFile(const std::string& path) : name_(path == "-" ? "<stdout>" : path), plan_(plan_output(path)) {
  switch (plan_.method) {
    case OutputMethod::StandardOutput: fd_ = STDOUT_FILENO; return;
    case OutputMethod::Direct:
      if (plan_.descriptor >= 0) {
        fd_ = ::fcntl(plan_.descriptor, F_DUPFD_CLOEXEC, 3);
      } else if (plan_.socket) {
        fd_ = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
        sockaddr_un address{};
        address.sun_family = AF_UNIX;
        if (fd_ >= 0 && plan_.target.size() >= sizeof address.sun_path) {
          ::close(fd_);
          fd_ = -1;
          errno = ENAMETOOLONG;
        }
        if (fd_ >= 0) {
          std::memcpy(address.sun_path, plan_.target.c_str(), plan_.target.size() + 1);
          if (::connect(fd_, reinterpret_cast<const sockaddr*>(&address), sizeof address) != 0) {
            const int error = errno;
            ::close(fd_);
            fd_ = -1;
            errno = error;
          }
        }
      } else {
        fd_ = ::open(plan_.target.c_str(), O_WRONLY | O_CLOEXEC | O_NOCTTY);
      }
      if (fd_ < 0) fail(errno);
      return;
    case OutputMethod::Replace: break;
  }
  std::error_code error;
  const fs::path target = fs::absolute(plan_.target, error);
  if (error) fail(error.value());
  plan_.target = target.string();
  struct stat existing {};
  const bool replaces = ::stat(plan_.target.c_str(), &existing) == 0 && S_ISREG(existing.st_mode);
  remove_stale_temporaries(plan_.target);
  install_cleanup_handler();
  const std::string prefix = temporary_prefix(plan_.target);
  static std::atomic<std::uint64_t> counter{0};
  std::mt19937_64 random(std::random_device{}() ^ (counter.fetch_add(1) * 0x9E3779B97F4A7C15ull));
  constexpr char kLetters[] = "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789";
  int open_error = EEXIST;
  for (int attempt = 0; attempt < 100 && fd_ < 0; ++attempt) {
    std::string candidate = prefix;
    for (int i = 0; i < 6; ++i) candidate += kLetters[random() % (sizeof kLetters - 1)];
    // In the handler's table before the file exists: a signal may run the
    // handler on any thread, even between the open and the next line. A name
    // that already exists carries this process id, so it is a leftover of
    // this pid that remove_stale_temporaries would remove anyway.
    const int slot = claim_slot(candidate);
    fd_ = ::open(candidate.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);  // the umask applies
    // A cleanup signal taken on another thread that did not see this slot
    // live (it is marked before g_dying is read here, and the handler sets
    // g_dying before it reads the slots) leaves this file to us: the process
    // is about to end.
    if (fd_ >= 0 && g_dying.load()) ::unlink(candidate.c_str());
    if (fd_ >= 0) {
      temporary_ = candidate;
      slot_ = slot;
    } else {
      release_slot(slot);
      if ((open_error = errno) != EEXIST) break;
    }
  }
  if (fd_ < 0) {
    throw IoError(fmt::format("{}: cannot write: {} (creating a temporary file in {})", name_, errno_text(open_error),
                              folder_of(target).string()));
  }
  if (replaces) ::fchmod(fd_, existing.st_mode & 07777);  // the replaced file's permissions
}

OutputFile::~OutputFile() {
  if (!done_) abandon();
}

void OutputFile::fail(int error) const { throw IoError(fmt::format("{}: cannot write: {}", name_, errno_text(error))); }

void OutputFile::write(std::string_view bytes) {
  if (done_) throw IoError(fmt::format("{}: cannot write: the output is already closed", name_));
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t wrote = ::write(fd_, bytes.data() + done, bytes.size() - done);
    if (wrote < 0) {
      if (errno == EINTR) continue;
      fail(errno);
    }
    done += static_cast<std::size_t>(wrote);
  }
}

void OutputFile::commit() {
  if (done_) return;
  const auto give_up = [&](int error) {
    abandon();
    fail(error);
  };
  switch (plan_.method) {
    case OutputMethod::StandardOutput: break;
    case OutputMethod::Direct: {
      const int result = ::close(fd_);
      fd_ = -1;
      if (result != 0 && errno != EINTR) give_up(errno);
      break;
    }
    case OutputMethod::Replace: {
      if (::fsync(fd_) != 0) give_up(errno);
      const int result = ::close(fd_);
      fd_ = -1;
      if (result != 0 && errno != EINTR) give_up(errno);
      if (::rename(temporary_.c_str(), plan_.target.c_str()) != 0) give_up(errno);
      release_slot(slot_);
      slot_ = -1;
      temporary_.clear();
      // The rename itself lasts once the folder is on disk; a folder that
      // cannot be synced (some file systems) leaves it to the kernel.
      const int folder = ::open(folder_of(plan_.target).c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
      if (folder >= 0) {
        ::fsync(folder);
        ::close(folder);
      }
      break;
    }
  }
  done_ = true;
}

void OutputFile::abandon() noexcept {
  if (fd_ >= 0 && plan_.method != OutputMethod::StandardOutput) ::close(fd_);
  fd_ = -1;
  if (!temporary_.empty()) ::unlink(temporary_.c_str());
  release_slot(slot_);
  slot_ = -1;
  temporary_.clear();
  done_ = true;
}

}  // namespace nodetrace::base
