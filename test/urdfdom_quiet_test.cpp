// urdfdom prints through console_bridge ("material ... undefined", a dozen
// lines for TIAGo's URDF); the library never prints. Loading every shared
// URDF leaves stderr empty, and the handler an application installed is
// the one in place afterwards.
#include <console_bridge/console.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <functional>
#include <string>

#include "stac/robot_model.hpp"
#include "support/test_util.hpp"

namespace stac {
namespace {

// What `f` writes to file descriptor 2.
std::string stderrOf(const std::function<void()>& f) {
  std::fflush(stderr);
  FILE* sink = std::tmpfile();
  const int saved = dup(2);
  dup2(fileno(sink), 2);
  f();
  std::fflush(stderr);
  dup2(saved, 2);
  close(saved);
  std::rewind(sink);
  std::string out;
  char buf[512];
  while (const size_t n = std::fread(buf, 1, sizeof buf, sink)) out.append(buf, n);
  std::fclose(sink);
  return out;
}

std::vector<std::string> sharedUrdfs() {
  std::vector<std::string> out = test::externalUrdfs();
  const std::string tiago = std::string(STAC_REALDATA_DIR) + "/tiago/tiago_48_schunk.urdf";
  if (std::string(STAC_REALDATA_DIR) != "" && std::ifstream(tiago).good()) out.push_back(tiago);
  return out;
}

TEST(UrdfdomQuiet, CaptureSeesStderr) {  // the check below can fail
  EXPECT_EQ(stderrOf([] { std::fprintf(stderr, "material undefined\n"); }),
            "material undefined\n");
}

TEST(UrdfdomQuiet, LoadingTheSharedUrdfsPrintsNothing) {
  const std::vector<std::string> urdfs = sharedUrdfs();
  if (urdfs.empty()) GTEST_SKIP() << "STAC_ROBOTS_DIR / STAC_REALDATA_DIR not set";
  for (const std::string& urdf : urdfs)
    EXPECT_EQ(stderrOf([&] { RobotModel::fromFile(urdf); }), "") << urdf;
}

struct Counting : console_bridge::OutputHandler {
  void log(const std::string&, console_bridge::LogLevel, const char*, int) override { ++count; }
  int count = 0;
};

TEST(UrdfdomQuiet, TheApplicationsHandlerIsPutBack) {
  const std::vector<std::string> urdfs = sharedUrdfs();
  if (urdfs.empty()) GTEST_SKIP() << "STAC_ROBOTS_DIR / STAC_REALDATA_DIR not set";
  console_bridge::OutputHandler* before = console_bridge::getOutputHandler();
  Counting mine;
  console_bridge::useOutputHandler(&mine);
  RobotModel::fromFile(urdfs.back());
  EXPECT_EQ(console_bridge::getOutputHandler(), &mine);
  EXPECT_EQ(mine.count, 0);  // urdfdom's messages went to the library's guard
  console_bridge::log(__FILE__, __LINE__, console_bridge::CONSOLE_BRIDGE_LOG_ERROR, "after");
  EXPECT_EQ(mine.count, 1);  // and the application's own logging still reaches it
  console_bridge::useOutputHandler(before);
}

}  // namespace
}  // namespace stac
