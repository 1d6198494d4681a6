// stac_calib --holdout: the end of the log is kept out of the fit and the
// cross-sensor table printed on it must be exactly what stac_eval reports
// for the same calibration on the same frames.
#include <gtest/gtest.h>

#include <sstream>

#include "stac/log.hpp"
#include "support/arm_files.hpp"
#include "support/test_util.hpp"

namespace stac {
namespace {

std::vector<std::string> tokens(const std::string& line) {
  std::istringstream in(line);
  std::vector<std::string> out;
  for (std::string t; in >> t;) out.push_back(t);
  return out;
}

// The line of `text` whose first token is `first`.
std::string lineStartingWith(const std::string& text, const std::string& first) {
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    const auto t = tokens(line);
    if (!t.empty() && t[0] == first) return line;
  }
  return "";
}

class HoldoutCli : public ::testing::Test {
 protected:
  void SetUp() override {
    test::writeFile(file("arm.urdf"), test::kArmUrdf);
    test::writeFile(file("truth.yaml"), test::kArmTruth);
    test::writeFile(file("seed.yaml"), test::kArmSeed);
    const auto r = test::runCommand(test::appPath("stac_simulate") + " --urdf " + file("arm.urdf") +
                                    " --sensors " + file("truth.yaml") + " --frames 300 --log " +
                                    file("data.csv") + " --seed 11");
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  std::string file(const std::string& n) const { return dir_.file(n); }
  test::CommandResult calib(const std::string& extra) const {
    return test::runCommand(test::appPath("stac_calib") + " --urdf " + file("arm.urdf") +
                            " --log " + file("data.csv") + " --sensors " + file("seed.yaml") +
                            " --quiet " + extra);
  }
  test::TempDir dir_;
};

TEST_F(HoldoutCli, FitsTheStartAndPredictsTheEndLikeStacEval) {
  const auto r = calib("--holdout 0.3 --output " + file("cal.yaml") + " --joint-angles " +
                       file("q.csv"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("held out: the last 90 of 300 frames"), std::string::npos) << r.out;
  // The fit saw 210 frames only: the summary and the joint angles say so.
  EXPECT_NE(test::readFile(file("cal.yaml")).find("frames: 210"), std::string::npos);
  const Log q = readLog(file("q.csv"));
  EXPECT_EQ(q.numFrames(), 210);

  // The last 90 rows of the log, evaluated by stac_eval, give the same row.
  const Log log = readLog(file("data.csv"));
  Log tail = log;
  tail.values = log.values.bottomRows(90);
  tail.time.assign(log.time.end() - 90, log.time.end());
  writeLog(file("test.csv"), tail);
  for (const std::string use : {"marker", "joint", "tendon", "joint+tendon", "marker+joint+tendon"}) {
    std::string groups = use;
    for (char& c : groups) c = c == '+' ? ',' : c;
    const auto e = test::runCommand(test::appPath("stac_eval") + " --urdf " + file("arm.urdf") +
                                    " --sensors " + file("cal.yaml") + " --log " +
                                    file("test.csv") + " --use " + groups);
    ASSERT_EQ(e.exit_code, 0) << e.err;
    // stac_eval's table row is the line after its "marker (m) ..." header.
    const std::string eval_out = e.out;
    const size_t head = eval_out.find("marker (m)");
    ASSERT_NE(head, std::string::npos) << eval_out;
    const size_t row_begin = eval_out.find('\n', head) + 1;
    const std::string eval_row = eval_out.substr(row_begin, eval_out.find('\n', row_begin) - row_begin);
    auto expected = tokens(eval_row);
    auto got = tokens(lineStartingWith(r.out.substr(r.out.find("held out")), use));
    ASSERT_FALSE(got.empty()) << "no row '" << use << "' in:\n" << r.out;
    got.erase(got.begin());
    EXPECT_EQ(got, expected) << use;
  }
  // Markers predicted from the pots on unseen frames: a few σ (2 mm) at most.
  const auto row = tokens(lineStartingWith(r.out.substr(r.out.find("held out")), "joint"));
  ASSERT_GE(row.size(), 2u);
  EXPECT_LT(std::stod(row[1]), 0.01) << r.out;
}

TEST_F(HoldoutCli, BadFractionsExitTwoAndWriteNothing) {
  for (const std::string bad : {"0", "1", "-0.2", "abc", "1.5"}) {
    const auto before = dir_.list();
    const auto r = calib("--holdout " + bad + " --output " + file("cal.yaml"));
    EXPECT_EQ(r.exit_code, 2) << bad;
    EXPECT_NE(r.err.find("--holdout"), std::string::npos) << r.err;
    EXPECT_EQ(dir_.list(), before) << bad;
  }
  // 0.999 of 300 frames leaves a single frame to fit: refused, naming the log.
  const auto r = calib("--holdout 0.999 --output " + file("cal.yaml"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find(file("data.csv")), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("no frame to fit"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace stac
