// The output rule (formats/output_file.hpp) for each kind of path: a new name,
// a regular file, a symbolic link, a FIFO with a reader, a socket, /dev/null
// and /dev/full (written directly, never renamed over), a read-only folder, a
// missing folder; and the removal of temporaries.
#include <fcntl.h>
#include <linux/fs.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <pthread.h>
#include <signal.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <functional>
#include <fstream>
#include <future>
#include <thread>

#include "nodetrace/base/error.hpp"
#include "nodetrace/base/output_file.hpp"
#include "nodetrace/base/standard_output.hpp"
#include "test_support.hpp"

namespace nodetrace::base {
namespace {

namespace fs = std::filesystem;
using nodetrace::testing::read_file;
using nodetrace::testing::TempDir;
using nodetrace::testing::temporaries;
using nodetrace::testing::write_file;

std::string io_error_of(const std::function<void()>& body) {
  try {
    body();
  } catch (const IoError& error) {
    return error.what();
  }
  return {};
}

bool is_char_device(const char* path) {
  struct stat info {};
  return ::lstat(path, &info) == 0 && S_ISCHR(info.st_mode);
}

TEST(OutputPlan, EachKindOfPath) {
  TempDir dir;
  EXPECT_EQ(plan_output("-").method, OutputMethod::StandardOutput);

  const OutputPlan fresh = plan_output((dir / "new.din.zst").string());
  EXPECT_EQ(fresh.method, OutputMethod::Replace);
  EXPECT_EQ(fresh.target, (dir / "new.din.zst").string());

  write_file(dir / "old.din", "0 1\n");
  EXPECT_EQ(plan_output((dir / "old.din").string()).method, OutputMethod::Replace);

  fs::create_directory(dir / "archive");
  fs::create_symlink("archive/t.din.zst", dir / "link.din.zst");
  const OutputPlan link = plan_output((dir / "link.din.zst").string());
  EXPECT_EQ(link.method, OutputMethod::Replace);
  EXPECT_EQ(fs::path(link.target), dir / "archive/t.din.zst");

  ASSERT_EQ(::mkfifo((dir / "pipe").c_str(), 0600), 0);
  EXPECT_EQ(plan_output((dir / "pipe").string()).method, OutputMethod::Direct);
  fs::create_symlink("pipe", dir / "pipe-link");
  EXPECT_EQ(plan_output((dir / "pipe-link").string()).method, OutputMethod::Direct);

  for (const char* device : {"/dev/null", "/dev/full"}) {
    const OutputPlan plan = plan_output(device);
    EXPECT_EQ(plan.method, OutputMethod::Direct) << device;
    EXPECT_EQ(plan.target, device);
  }
  const OutputPlan standard = plan_output("/dev/stdout");
  EXPECT_EQ(standard.method, OutputMethod::Direct);
  EXPECT_EQ(standard.descriptor, 1);
  EXPECT_EQ(plan_output("/proc/self/fd/2").descriptor, 2);

  const std::string directory_error = io_error_of([&] { plan_output(dir.path().string()); });
  EXPECT_NE(directory_error.find(": cannot write: is a directory"), std::string::npos) << directory_error;
  fs::create_symlink("loop-b", dir / "loop-a");
  fs::create_symlink("loop-a", dir / "loop-b");
  const std::string loop_error = io_error_of([&] { plan_output((dir / "loop-a").string()); });
  EXPECT_NE(loop_error.find("cannot write: Too many levels of symbolic links"), std::string::npos) << loop_error;
}

TEST(OutputFile, RegularFileIsReplacedOnlyWhenCommitted) {
  TempDir dir;
  const fs::path target = dir / "t.din";
  write_file(target, "old");
  ASSERT_EQ(::chmod(target.c_str(), 0640), 0);
  {
    OutputFile out(target.string());
    EXPECT_EQ(out.method(), OutputMethod::Replace);
    out.write("new bytes");
    EXPECT_EQ(read_file(target), "old");
    const auto pending = temporaries(dir.path());
    ASSERT_EQ(pending.size(), 1u);
    EXPECT_EQ(pending[0].rfind(".t.din.tmp-" + std::to_string(::getpid()) + "-", 0), 0u) << pending[0];
    out.commit();
  }
  EXPECT_EQ(read_file(target), "new bytes");
  EXPECT_EQ(fs::status(target).permissions() & fs::perms::all,
            fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read);
  EXPECT_TRUE(temporaries(dir.path()).empty());
}

TEST(OutputFile, AbandonedOutputLeavesTheTargetAndNoTemporary) {
  TempDir dir;
  write_file(dir / "kept.din", "old");
  {
    OutputFile out((dir / "kept.din").string());
    out.write("partial");
  }
  {
    OutputFile out((dir / "never.din").string());
    out.write("partial");
    out.abandon();
  }
  EXPECT_EQ(read_file(dir / "kept.din"), "old");
  EXPECT_FALSE(fs::exists(dir / "never.din"));
  EXPECT_TRUE(temporaries(dir.path()).empty());
}

TEST(OutputFile, SymlinkTargetIsReplacedAndTheLinkKept) {
  TempDir dir;
  fs::create_directory(dir / "archive");
  write_file(dir / "archive/t.din", "old");
  fs::create_symlink("archive/t.din", dir / "link.din");
  fs::create_symlink("archive/fresh.din", dir / "dangling.din");
  for (const char* name : {"link.din", "dangling.din"}) {
    OutputFile out((dir / name).string());
    out.write(name);
    out.commit();
  }
  EXPECT_TRUE(fs::is_symlink(dir / "link.din"));
  EXPECT_TRUE(fs::is_symlink(dir / "dangling.din"));
  EXPECT_EQ(read_file(dir / "archive/t.din"), "link.din");
  EXPECT_EQ(read_file(dir / "archive/fresh.din"), "dangling.din");
  EXPECT_TRUE(temporaries(dir.path()).empty());
  EXPECT_TRUE(temporaries(dir / "archive").empty());
}

TEST(OutputFile, FifoIsWrittenToItsReaderAndStaysAFifo) {
  TempDir dir;
  const fs::path fifo = dir / "pipe";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  auto reader = std::async(std::launch::async, [&] {
    std::ifstream in(fifo, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  });
  const std::string bytes(100000, 'x');
  {
    OutputFile out(fifo.string());
    EXPECT_EQ(out.method(), OutputMethod::Direct);
    out.write(bytes);
    out.commit();
  }
  EXPECT_EQ(reader.get(), bytes);
  EXPECT_TRUE(fs::is_fifo(fifo));
  EXPECT_TRUE(temporaries(dir.path()).empty());
}

TEST(OutputFile, SocketIsConnectedTo) {
  TempDir dir;
  const fs::path path = dir / "sock";
  const int server = ::socket(AF_UNIX, SOCK_STREAM, 0);
  ASSERT_GE(server, 0);
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  ASSERT_LT(path.string().size(), sizeof address.sun_path);
  std::strcpy(address.sun_path, path.c_str());
  ASSERT_EQ(::bind(server, reinterpret_cast<sockaddr*>(&address), sizeof address), 0);
  ASSERT_EQ(::listen(server, 1), 0);
  auto reader = std::async(std::launch::async, [&] {
    const int client = ::accept(server, nullptr, nullptr);
    std::string got;
    char buffer[4096];
    for (ssize_t n; (n = ::read(client, buffer, sizeof buffer)) > 0;) got.append(buffer, static_cast<std::size_t>(n));
    ::close(client);
    return got;
  });
  {
    OutputFile out(path.string());
    out.write("records");
    out.commit();
  }
  EXPECT_EQ(reader.get(), "records");
  ::close(server);
  EXPECT_TRUE(fs::is_socket(path));
}

TEST(OutputFile, DevNullIsWrittenDirectly) {
  OutputFile out("/dev/null");
  EXPECT_EQ(out.method(), OutputMethod::Direct);
  out.write("discarded");
  out.commit();
  EXPECT_TRUE(is_char_device("/dev/null"));
}

TEST(OutputFile, DevFullFailsWithTheReason) {
  const std::string error = io_error_of([] {
    OutputFile out("/dev/full");
    EXPECT_EQ(out.method(), OutputMethod::Direct);
    out.write("lost");
    out.commit();
  });
  EXPECT_EQ(error, "/dev/full: cannot write: No space left on device");
  EXPECT_TRUE(is_char_device("/dev/full"));
}

// A folder nobody can create files in; as root (who ignores permissions)
// the immutable attribute does it, where the file system has one.
class ReadOnlyFolder {
 public:
  explicit ReadOnlyFolder(const fs::path& path) : path_(path) {
    fs::create_directory(path_);
    ::chmod(path_.c_str(), 0555);
    if (::access(path_.c_str(), W_OK) != 0) {
      read_only_ = true;
      return;
    }
    fd_ = ::open(path_.c_str(), O_RDONLY | O_DIRECTORY);
    int flags = 0;
    if (fd_ >= 0 && ::ioctl(fd_, FS_IOC_GETFLAGS, &flags) == 0) {
      flags |= FS_IMMUTABLE_FL;
      read_only_ = ::ioctl(fd_, FS_IOC_SETFLAGS, &flags) == 0;
    }
  }
  ~ReadOnlyFolder() {
    if (fd_ >= 0) {
      int flags = 0;
      if (::ioctl(fd_, FS_IOC_GETFLAGS, &flags) == 0) {
        flags &= ~FS_IMMUTABLE_FL;
        ::ioctl(fd_, FS_IOC_SETFLAGS, &flags);
      }
      ::close(fd_);
    }
    ::chmod(path_.c_str(), 0755);
  }
  bool read_only() const { return read_only_; }

 private:
  fs::path path_;
  int fd_ = -1;
  bool read_only_ = false;
};

TEST(OutputFile, ReadOnlyFolderIsAnErrorNamingTheFolder) {
  TempDir dir;
  const ReadOnlyFolder folder(dir / "ro");
  if (!folder.read_only()) GTEST_SKIP() << "cannot make a folder read-only here (root without chattr support)";
  const std::string target = (dir / "ro/t.din.zst").string();
  const std::string error = io_error_of([&] { OutputFile out(target); });
  EXPECT_EQ(error.rfind(target + ": cannot write: ", 0), 0u) << error;
  EXPECT_NE(error.find("creating a temporary file in " + (dir / "ro").string()), std::string::npos) << error;
  EXPECT_TRUE(fs::is_empty(dir / "ro"));
}

TEST(OutputFile, MissingFolderIsAnError) {
  TempDir dir;
  const std::string target = (dir / "missing/t.din.zst").string();
  const std::string error = io_error_of([&] { OutputFile out(target); });
  EXPECT_EQ(error.rfind(target + ": cannot write: No such file or directory", 0), 0u) << error;
  EXPECT_FALSE(fs::exists(dir / "missing"));
}

TEST(OutputFile, StaleTemporariesOfDeadRunsAreRemoved) {
  TempDir dir;
  const pid_t child = ::fork();
  if (child == 0) ::_exit(0);
  ASSERT_GT(child, 0);
  ASSERT_EQ(::waitpid(child, nullptr, 0), child);  // a pid that no longer runs
  const std::string dead = ".t.din.zst.tmp-" + std::to_string(child) + "-abcdef";
  const std::string alive = ".t.din.zst.tmp-" + std::to_string(::getppid()) + "-ghijkl";
  const std::string other = ".u.din.zst.tmp-" + std::to_string(child) + "-abcdef";
  for (const auto& name : {dead, alive, other}) write_file(dir / name, "partial");
  {
    OutputFile out((dir / "t.din.zst").string());
    EXPECT_FALSE(fs::exists(dir / dead));
    out.write("whole");
    out.commit();
  }
  EXPECT_FALSE(fs::exists(dir / dead));
  EXPECT_TRUE(fs::exists(dir / alive));  // its writer may still be running
  EXPECT_TRUE(fs::exists(dir / other));  // another output's
  EXPECT_EQ(read_file(dir / "t.din.zst"), "whole");
}

// Run on top of the first SIGINT's handler, before its first line (see
// below): a second SIGINT to the process, which the thread that does not
// block it takes.
extern "C" void send_second_interrupt(int) {
  ::kill(::getpid(), SIGINT);
  ::sleep(10);  // the process ends meanwhile
}

// `timeout` sends SIGINT twice and users press Ctrl-C twice: a second signal
// taken on another thread while the first is being handled must not end the
// process before the temporary is removed. To put the second signal in that
// moment every time, SIGINT and SIGUSR1 are made pending together on a
// thread that blocks both, then unblocked at once: the kernel delivers the
// lower-numbered SIGINT first and runs SIGUSR1's handler on top of it,
// before the cleanup handler's first line.
TEST(OutputFile, ASecondSignalDuringCleanupStillRemovesTheTemporary) {
  TempDir dir;
  const pid_t child = ::fork();
  if (child == 0) {
    OutputFile out((dir / "t.din.zst").string());
    out.write("partial");
    std::thread other([] {
      for (;;) ::pause();
    });
    struct sigaction action {};
    action.sa_handler = send_second_interrupt;
    sigemptyset(&action.sa_mask);
    ::sigaction(SIGUSR1, &action, nullptr);
    sigset_t both;
    sigemptyset(&both);
    sigaddset(&both, SIGINT);
    sigaddset(&both, SIGUSR1);
    ::pthread_sigmask(SIG_BLOCK, &both, nullptr);
    ::pthread_kill(::pthread_self(), SIGINT);
    ::pthread_kill(::pthread_self(), SIGUSR1);
    ::pthread_sigmask(SIG_UNBLOCK, &both, nullptr);
    ::_exit(3);  // not reached: the SIGINT ends the process
  }
  ASSERT_GT(child, 0);
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGINT) << "status " << status;
  EXPECT_EQ(temporaries(dir.path()), std::vector<std::string>{});
  EXPECT_FALSE(fs::exists(dir / "t.din.zst"));
}

TEST(StandardOutput, FlushOfAWorkingOutputIsNoError) {
  EXPECT_EQ(flush_standard_output(), std::nullopt);
}

}  // namespace
}  // namespace nodetrace::base
