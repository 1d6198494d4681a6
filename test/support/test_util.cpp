#include "support/test_util.hpp"

#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <dirent.h>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <unistd.h>

#include "stac/simulate.hpp"

namespace stac::test {

std::string dataPath(const std::string& name) {
  return std::string(STAC_DATA_DIR) + "/" + name;
}

std::string appPath(const std::string& app) {
  return std::string(STAC_APPS_DIR) + "/" + app;
}

std::vector<std::string> externalUrdfs() {
  std::vector<std::string> out;
  // The environment's STAC_ROBOTS_DIR, when set, overrides the configured
  // one: the basin test then runs on other robots without a rebuild.
  const char* env = std::getenv("STAC_ROBOTS_DIR");
  const std::string dir = env && *env ? env : STAC_ROBOTS_DIR;
  if (dir.empty()) return out;
  if (DIR* d = opendir(dir.c_str())) {
    while (dirent* e = readdir(d)) {
      std::string n = e->d_name;
      if (n.size() > 5 && n.substr(n.size() - 5) == ".urdf") out.push_back(dir + "/" + n);
    }
    closedir(d);
  }
  std::sort(out.begin(), out.end());
  return out;
}

TempDir::TempDir() {
  const char* base = std::getenv("TMPDIR");
  std::string tmpl = std::string(base && *base ? base : "/tmp") + "/stac_test_XXXXXX";
  std::vector<char> buf(tmpl.begin(), tmpl.end());
  buf.push_back('\0');
  if (!mkdtemp(buf.data())) throw std::runtime_error("mkdtemp failed");
  path_ = buf.data();
}

TempDir::~TempDir() {
  std::string cmd = "rm -rf '" + path_ + "'";
  if (std::system(cmd.c_str()) != 0) {
  }
}

std::vector<std::string> TempDir::list() const {
  std::vector<std::string> out;
  if (DIR* d = opendir(path_.c_str())) {
    while (dirent* e = readdir(d)) {
      std::string n = e->d_name;
      if (n != "." && n != "..") out.push_back(n);
    }
    closedir(d);
  }
  std::sort(out.begin(), out.end());
  return out;
}

CommandResult runCommand(const std::string& command_line) {
  TempDir tmp;
  const std::string out = tmp.file("out"), err = tmp.file("err");
  const std::string cmd =
      command_line + " </dev/null >'" + out + "' 2>'" + err + "'";
  const int status = std::system(cmd.c_str());
  CommandResult r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = readFile(out);
  r.err = readFile(err);
  return r;
}

void writeFile(const std::string& path, const std::string& text) {
  std::ofstream f(path, std::ios::binary);
  f << text;
}

std::string readFile(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

Eigen::VectorXd randomQ(const RobotModel& model, std::mt19937& rng) {
  Eigen::VectorXd q(model.dof());
  for (int i = 0; i < model.dof(); ++i) {
    double lo = model.lowerLimits()[i], hi = model.upperLimits()[i];
    if (!std::isfinite(lo) || !std::isfinite(hi)) lo = -M_PI, hi = M_PI;
    q[i] = std::uniform_real_distribution<double>(lo, hi)(rng);
  }
  return q;
}

RowMatrix partialSwings(const RobotModel& robot, RowMatrix q, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const std::vector<JointRange> ranges = motionRanges(robot);
  for (int j = 0; j < robot.dof(); ++j) {
    const double lo = ranges[j].lower, hi = ranges[j].upper;
    if (!(hi > lo)) continue;
    const double width = (0.2 + 0.2 * u(rng)) * (hi - lo);
    const double start = lo + u(rng) * (hi - lo - width);
    const double qmin = q.col(j).minCoeff(), qmax = q.col(j).maxCoeff();
    if (!(qmax > qmin)) continue;
    q.col(j) = ((q.col(j).array() - qmin) * (width / (qmax - qmin)) + start).matrix();
  }
  return q;
}

RowMatrix staticPostures(const RobotModel& robot, int postures, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0.05, 0.95);
  const std::vector<JointRange> ranges = motionRanges(robot);
  RowMatrix q(postures, robot.dof());
  for (int t = 0; t < postures; ++t)
    for (int j = 0; j < robot.dof(); ++j)
      q(t, j) = ranges[j].lower + u(rng) * (ranges[j].upper - ranges[j].lower);
  return q;
}

}  // namespace stac::test
