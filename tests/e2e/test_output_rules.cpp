// Every program's outputs, end to end: reports on a full standard output are
// exit 1 naming it; an output that is a device, FIFO or symlink is written
// where it points, never renamed over; interrupted runs (SIGINT, SIGTERM,
// SIGHUP, SIGPIPE) leave neither the output nor a temporary, and after a
// SIGKILL the next run to the same name removes the temporary it left.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <future>
#include <random>
#include <thread>
#include <vector>

#include "test_support.hpp"

extern char** environ;

namespace nodetrace::testing {
namespace {

namespace fs = std::filesystem;

std::string quoted(const fs::path& path) { return shell_quoted(path); }

// Starts `argv` with standard output and error discarded; returns its pid.
pid_t spawn(const std::vector<std::string>& argv) {
  std::vector<char*> args;
  for (const auto& arg : argv) args.push_back(const_cast<char*>(arg.c_str()));
  args.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 2, "/dev/null", O_WRONLY, 0);
  pid_t pid = -1;
  const int error = posix_spawn(&pid, args[0], &actions, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  return error == 0 ? pid : -1;
}

// Waits (a bounded while: the program needs a moment to start writing) for
// the first temporary in `folder`; true once one is there.
bool wait_for_temporary(const fs::path& folder, pid_t pid) {
  for (int i = 0; i < 6000; ++i) {
    if (!temporaries(folder).empty()) return true;
    int status = 0;
    if (::waitpid(pid, &status, WNOHANG) == pid) return false;  // it ended first
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return false;
}

class OutputRules : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir();
    trace_ = *dir_ / "small.din.zst";
    const auto rendered = run_command(quoted(program("tracer")) + " render mountain --width 32 --height 24 -q -o " +
                                      quoted(trace_));
    ASSERT_EQ(rendered.exit_code, 0) << rendered.err;
    // A plain trace big enough that converting it at zstd level 19 on one
    // thread takes a while: time to interrupt it.
    big_ = *dir_ / "big.din";
    std::ofstream out(big_);
    char line[32];
    for (unsigned i = 0; i < 1500000; ++i) {
      std::snprintf(line, sizeof line, "0 %08x %02u\n", (i * 2654435761u) & 0xFFFFF8u, i % 23);
      out << line;
    }
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }
  static std::string bin(const char* name) { return quoted(program(name)); }

  std::vector<std::string> slow_convert(const fs::path& out) const {
    return {program("tracetool").string(), "convert", big_.string(), out.string(), "--zstd-level", "19",
            "--threads", "1", "--tags-are-levels"};
  }
  std::vector<std::string> slow_render(const fs::path& out) const {
    return {program("tracer").string(), "render", "mountain", "--width", "1600", "--height", "1200",
            "--threads", "1", "-q", "-o", out.string()};
  }

  static TempDir* dir_;
  static fs::path trace_;
  static fs::path big_;
};
TempDir* OutputRules::dir_ = nullptr;
fs::path OutputRules::trace_;
fs::path OutputRules::big_;

TEST_F(OutputRules, ReportsOnAFullStandardOutputAreExit1) {
  const std::string t = quoted(trace_);
  const std::string dinero = quoted(fs::path(program("cachesim").string() + " dinero"));
  const std::vector<std::string> commands = {
      bin("cachesim") + " run " + t + " --size 4k",
      bin("cachesim") + " run " + t + " --size 4k --format csv",
      bin("cachesim") + " dinero -informat d -l1-dsize 8k -l1-dbsize 8 -l1-dassoc 1 " + t,
      bin("cachesim") + " --help",
      bin("cachesim") + " run --help",
      bin("dinero-wrap") + " run " + t + " --size 4k --dinero " + dinero,
      bin("dinero-wrap") + " --help",
      bin("tracetool") + " info " + t,
      bin("tracetool") + " verify " + t,
      bin("tracetool") + " cat " + t,
      bin("tracetool") + " --help",
      bin("tracer") + " info mountain",
      bin("tracer") + " scenes",
      bin("tracer") + " render mountain --width 8 --height 6 -q -o -",
      bin("tracer") + " --help",
  };
  for (const auto& command : commands) {
    const auto result = run_command(command + " >/dev/full");
    EXPECT_EQ(result.exit_code, 1) << command;
    EXPECT_NE(result.err.find("<stdout>: cannot write: No space left on device"), std::string::npos)
        << command << "\n" << result.err;
  }
}

// Issue 52 item 12: a lost report names the subcommand as the command's
// other errors do ("cachesim run: <stdout>: ..."), full disk or closed pipe.
TEST_F(OutputRules, LostReportsNameTheSubcommand) {
  const std::string t = quoted(trace_);
  const std::vector<std::pair<std::string, std::string>> commands = {
      {"cachesim run", bin("cachesim") + " run " + t + " --size 4k"},
      {"cachesim dinero", bin("cachesim") + " dinero -informat d -l1-dsize 8k -l1-dbsize 8 " + t},
      {"tracetool info", bin("tracetool") + " info " + t},
      {"tracetool cat", bin("tracetool") + " cat " + t},
      {"tracer scenes", bin("tracer") + " scenes"},
  };
  for (const auto& [name, command] : commands) {
    const auto full = run_command(command + " >/dev/full");
    EXPECT_EQ(full.exit_code, 1) << command;
    EXPECT_EQ(full.err, name + ": <stdout>: cannot write: No space left on device\n") << command;
  }
  // A reader that stops early, with SIGPIPE ignored as some shells and
  // pipelines leave it: the write fails with EPIPE.
  const auto piped = run_command("trap '' PIPE; " + bin("tracetool") + " cat " + t + " | head -c 10 >/dev/null");
  EXPECT_EQ(piped.err, "tracetool cat: <stdout>: cannot write: Broken pipe\n");
  // Without a subcommand the program names itself.
  EXPECT_EQ(run_command(bin("cachesim") + " --help >/dev/full").err,
            "cachesim: <stdout>: cannot write: No space left on device\n");
}

TEST_F(OutputRules, DevNullAndFifosAreWrittenNotReplaced) {
  for (const std::string& command :
       {bin("tracer") + " render mountain --width 16 --height 12 -q -o /dev/null --image /dev/null",
        bin("tracetool") + " convert " + quoted(trace_) + " /dev/null"}) {
    const auto result = run_command(command);
    EXPECT_EQ(result.exit_code, 0) << command << "\n" << result.err;
    struct stat info {};
    ASSERT_EQ(::lstat("/dev/null", &info), 0);
    EXPECT_TRUE(S_ISCHR(info.st_mode)) << "/dev/null was replaced by: " << command;
  }
  TempDir dir;
  const fs::path fifo = dir / "stream.din.zst";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  auto reader = std::async(std::launch::async, [&] { return run_command(bin("tracetool") + " verify - <" + quoted(fifo)); });
  const auto rendered = run_command(bin("tracer") + " render mountain --width 16 --height 12 -q -o " + quoted(fifo));
  EXPECT_EQ(rendered.exit_code, 0) << rendered.err;
  const auto verified = reader.get();
  EXPECT_EQ(verified.exit_code, 0) << verified.err;
  EXPECT_EQ(verified.out.rfind("OK: ", 0), 0u) << verified.out;
  EXPECT_TRUE(fs::is_fifo(fifo));
  const auto full = run_command(bin("tracetool") + " convert " + quoted(trace_) + " /dev/full");
  EXPECT_EQ(full.exit_code, 1);
  EXPECT_NE(full.err.find("/dev/full: cannot write: No space left on device"), std::string::npos) << full.err;
}

TEST_F(OutputRules, SymlinkedOutputReplacesItsTarget) {
  TempDir dir;
  fs::create_directory(dir / "archive");
  fs::create_symlink("archive/t.din.zst", dir / "link.din.zst");
  const auto result = run_command(bin("tracetool") + " convert " + quoted(trace_) + " " + quoted(dir / "link.din.zst"));
  EXPECT_EQ(result.exit_code, 0) << result.err;
  EXPECT_TRUE(fs::is_symlink(dir / "link.din.zst"));
  EXPECT_EQ(run_command(bin("tracetool") + " verify " + quoted(dir / "archive/t.din.zst")).exit_code, 0);
}

TEST_F(OutputRules, InterruptedRunsLeaveNoOutputAndNoTemporary) {
  for (const bool render : {false, true}) {
    for (const int signal_number : {SIGINT, SIGTERM, SIGHUP, SIGPIPE}) {
      TempDir dir;
      const fs::path out = dir / "t.din.zst";
      const pid_t pid = spawn(render ? slow_render(out) : slow_convert(out));
      ASSERT_GT(pid, 0);
      const bool writing = wait_for_temporary(dir.path(), pid);
      if (writing) ::kill(pid, signal_number);
      int status = 0;
      ::waitpid(pid, &status, 0);
      ASSERT_TRUE(writing) << "the run ended before it could be interrupted";
      const std::string what = std::string(render ? "tracer render" : "tracetool convert") + ", signal " +
                               std::to_string(signal_number);
      EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == signal_number) << what << ": status " << status;
      EXPECT_FALSE(fs::exists(out)) << what;
      EXPECT_TRUE(temporaries(dir.path()).empty()) << what;
    }
  }
}

// As `timeout -s INT` does (the process, then its group: two signals) at
// random moments of a run, from before its output is opened to the middle
// of the writing: no run leaves a temporary. (The moment that used to leave
// one, a second signal during the first one's cleanup, is rare here; the
// base test ASecondSignalDuringCleanupStillRemovesTheTemporary makes it.)
TEST_F(OutputRules, InterruptsAtRandomMomentsLeaveNoTemporary) {
  const unsigned seed = std::random_device{}();
  std::mt19937 random(seed);
  for (int run = 0; run < 20; ++run) {
    TempDir dir;
    const fs::path out = dir / "t.din.zst";
    const pid_t pid = spawn(slow_convert(out));
    ASSERT_GT(pid, 0);
    const auto delay = std::chrono::microseconds(std::uniform_int_distribution<int>(0, 300000)(random));
    const auto gap = std::chrono::microseconds(std::uniform_int_distribution<int>(0, 100)(random));
    std::this_thread::sleep_for(delay);
    ::kill(pid, SIGINT);
    std::this_thread::sleep_for(gap);
    ::kill(pid, SIGINT);
    int status = 0;
    ::waitpid(pid, &status, 0);
    const std::string what = "seed " + std::to_string(seed) + ", run " + std::to_string(run) + ": SIGINT after " +
                             std::to_string(delay.count()) + " us, again " + std::to_string(gap.count()) + " us later";
    EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGINT) << what << ": status " << status;
    EXPECT_EQ(temporaries(dir.path()), std::vector<std::string>{}) << what;
    EXPECT_FALSE(fs::exists(out)) << what;
  }
}

TEST_F(OutputRules, NextRunRemovesTheTemporaryASigkillLeft) {
  TempDir dir;
  const fs::path out = dir / "t.din.zst";
  const pid_t pid = spawn(slow_convert(out));
  ASSERT_GT(pid, 0);
  const bool writing = wait_for_temporary(dir.path(), pid);
  if (writing) ::kill(pid, SIGKILL);
  ::waitpid(pid, nullptr, 0);
  ASSERT_TRUE(writing);
  const auto left = temporaries(dir.path());
  ASSERT_EQ(left.size(), 1u);
  EXPECT_EQ(left[0].rfind(".t.din.zst.tmp-" + std::to_string(pid) + "-", 0), 0u) << left[0];
  EXPECT_FALSE(fs::exists(out));
  const auto again = run_command(bin("tracetool") + " convert " + quoted(trace_) + " " + quoted(out));
  EXPECT_EQ(again.exit_code, 0) << again.err;
  EXPECT_TRUE(temporaries(dir.path()).empty());
  EXPECT_EQ(run_command(bin("tracetool") + " verify " + quoted(out)).exit_code, 0);
}

}  // namespace
}  // namespace nodetrace::testing
