// Ctrl-C and SIGTERM during a calibration (SPEC §4): stac_calib stops at its
// next poll, writes nothing (no output, no temporary file), prints one line
// and exits 128 + the signal. The signal is sent after the first progress
// line, i.e. in the middle of the run: with --tolerance 0 the runs below
// would go on for about ten seconds.
#include <gtest/gtest.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <sstream>
#include <string>
#include <vector>

#include "support/test_util.hpp"

namespace stac {
namespace {

struct Interrupted {
  int exit_code = -1;     // -1: did not exit normally
  std::string err;        // all of stderr
  bool saw_progress = false;
  double seconds_after_signal = 0;
};

// Runs argv with stderr on a pipe, sends `signal_number` once the first
// line arrives on stderr, and collects the rest.
Interrupted runAndInterrupt(const std::vector<std::string>& argv, int signal_number) {
  int fds[2];
  if (::pipe(fds) != 0) return {};
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::dup2(fds[1], STDERR_FILENO);
    ::close(fds[0]);
    ::close(fds[1]);
    std::vector<char*> args;
    for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    ::execv(args[0], args.data());
    ::_exit(127);
  }
  ::close(fds[1]);
  Interrupted r;
  std::chrono::steady_clock::time_point sent;
  char buf[4096];
  for (;;) {
    pollfd p{fds[0], POLLIN, 0};
    if (::poll(&p, 1, 60000) <= 0) break;  // 60 s without output: give up
    const ssize_t n = ::read(fds[0], buf, sizeof buf);
    if (n <= 0) break;
    r.err.append(buf, static_cast<size_t>(n));
    if (!r.saw_progress && r.err.find('\n') != std::string::npos) {
      r.saw_progress = true;
      sent = std::chrono::steady_clock::now();
      ::kill(pid, signal_number);
    }
  }
  ::close(fds[0]);
  if (!r.saw_progress) ::kill(pid, SIGKILL);
  int status = 0;
  ::waitpid(pid, &status, 0);
  r.seconds_after_signal =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - sent).count();
  if (WIFEXITED(status)) r.exit_code = WEXITSTATUS(status);
  return r;
}

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);) out.push_back(l);
  return out;
}

class InterruptCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new test::TempDir();
    const test::CommandResult sim = test::runCommand(
        test::appPath("stac_simulate") + " --urdf " + test::dataPath("hand24.urdf") +
        " --sensors " + test::dataPath("hand24_truth.yaml") + " --frames 300 --log " +
        dir_->file("data.csv"));
    ASSERT_EQ(sim.exit_code, 0) << sim.err;
  }
  static void TearDownTestSuite() { delete dir_; }

  // stac_calib on the hand, told to iterate until stopped.
  static std::vector<std::string> calib(const std::string& method) {
    return {test::appPath("stac_calib"), "--urdf", test::dataPath("hand24.urdf"),
            "--sensors", test::dataPath("hand24_seed.yaml"), "--log", dir_->file("data.csv"),
            "--output", dir_->file("out.yaml"), "--joint-angles", dir_->file("q.csv"),
            "--report", dir_->file("report.html"), "--threads", "1", "--tolerance", "0",
            "--max-iterations", "100000", "--method", method};
  }

  // Exit 128 + signal, progress lines then exactly `message`, and the
  // folder as it was (only the log: no output, no temporary file).
  static void expectStopped(const Interrupted& r, int code, const std::string& message) {
    ASSERT_TRUE(r.saw_progress) << r.err;
    EXPECT_EQ(r.exit_code, code) << r.err;
    const std::vector<std::string> ls = lines(r.err);
    ASSERT_GE(ls.size(), 2u) << r.err;
    EXPECT_EQ(ls.back(), message);
    for (size_t i = 0; i + 1 < ls.size(); ++i)
      EXPECT_EQ(ls[i].find("stac_calib"), std::string::npos) << "not a progress line: " << ls[i];
    EXPECT_EQ(dir_->list(), std::vector<std::string>{"data.csv"});
    // It stopped at the next poll, not at the end of the run.
    EXPECT_LT(r.seconds_after_signal, 5.0);
  }
  static test::TempDir* dir_;
};
test::TempDir* InterruptCli::dir_ = nullptr;

TEST_F(InterruptCli, SigintDuringStacStopsWithNothingWritten) {
  expectStopped(runAndInterrupt(calib("stac"), SIGINT), 130,
                "stac_calib: interrupted by SIGINT: no output written");
}

// --method joint: the signal lands inside a Ceres solve, which the library
// aborts after its current iteration (CalibrationOptions::should_stop).
TEST_F(InterruptCli, SigtermDuringJointSolveStopsWithNothingWritten) {
  expectStopped(runAndInterrupt(calib("joint"), SIGTERM), 143,
                "stac_calib: interrupted by SIGTERM: no output written");
}

// Before the calibration starts nothing can be half written: the process
// ends at once, with the same line (here blocked opening a FIFO no one
// writes).
TEST_F(InterruptCli, SignalWhileReadingEndsAtOnce) {
  const std::string fifo = dir_->file("fifo.csv");
  const test::CommandResult r = test::runCommand(
      "mkfifo " + fifo + " && { " + test::appPath("stac_calib") + " --urdf " +
      test::dataPath("hand24.urdf") + " --log " + fifo + " --output " + dir_->file("out.yaml") +
      " & pid=$!; sleep 1; kill -INT $pid; wait $pid; code=$?; rm " + fifo + "; exit $code; }");
  EXPECT_EQ(r.exit_code, 130) << r.err;
  EXPECT_EQ(r.err, "stac_calib: interrupted by SIGINT: no output written\n");
  EXPECT_EQ(dir_->list(), std::vector<std::string>{"data.csv"});
}

}  // namespace
}  // namespace stac
