// Shared helpers for the test suites.
#pragma once

#include <Eigen/Core>
#include <random>
#include <string>
#include <vector>

#include "stac/log.hpp"
#include "stac/robot_model.hpp"

namespace stac::test {

std::string dataPath(const std::string& name);    // data/<name>
std::string appPath(const std::string& app);      // build/apps/<app>
// Third-party URDFs (../shared/robots), empty when not configured.
std::vector<std::string> externalUrdfs();

// A fresh directory removed at scope exit.
class TempDir {
 public:
  TempDir();
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::string& path() const { return path_; }
  std::string file(const std::string& name) const { return path_ + "/" + name; }
  // Names of the files now in the directory, sorted.
  std::vector<std::string> list() const;

 private:
  std::string path_;
};

struct CommandResult {
  int exit_code = -1;
  std::string out, err;
};
// Runs a shell command line with stdin from /dev/null.
CommandResult runCommand(const std::string& command_line);

void writeFile(const std::string& path, const std::string& text);
std::string readFile(const std::string& path);

// Uniform q inside the joint limits (±pi where a joint has none).
Eigen::VectorXd randomQ(const RobotModel& model, std::mt19937& rng);

// Each joint of q (one row per frame) moved over a random 20-40% of its
// range, off-centre: its column squeezed into a random sub-interval (the
// issue's partial swings).
RowMatrix partialSwings(const RobotModel& robot, RowMatrix q, std::mt19937_64& rng);

// `postures` static postures (frames x dof), each joint uniform over the
// central 90% of its range, independent from posture to posture (a
// recording of postures held still, as the TIAGo's: no motion in time).
RowMatrix staticPostures(const RobotModel& robot, int postures, std::mt19937_64& rng);

}  // namespace stac::test
