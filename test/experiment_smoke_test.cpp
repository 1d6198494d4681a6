// stac_experiment end to end at smoke size: each experiment runs, writes its
// CSV (header and one row per run) and a well-formed SVG, and prints its
// Markdown table; and the numbers in them say what the experiment is for.
#include <gtest/gtest.h>
#include <tinyxml.h>

#include <sstream>

#include "support/test_util.hpp"

namespace stac {
namespace {

std::vector<std::vector<std::string>> readCsv(const std::string& path) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream in(test::readFile(path));
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> cells;
    std::stringstream ls(line);
    for (std::string c; std::getline(ls, c, ',');) cells.push_back(c);
    rows.push_back(cells);
  }
  return rows;
}

int column(const std::vector<std::string>& header, const std::string& name) {
  for (size_t i = 0; i < header.size(); ++i)
    if (header[i] == name) return static_cast<int>(i);
  ADD_FAILURE() << "no column " << name;
  return 0;
}

class ExperimentSmoke : public ::testing::Test {
 protected:
  test::CommandResult run(const std::string& which) {
    return test::runCommand(test::appPath("stac_experiment") + " --run " + which +
                            " --size smoke --data " + test::dataPath("") + " --out " + dir_.file(""));
  }
  void expectSvg(const std::string& name) {
    TiXmlDocument doc;
    ASSERT_TRUE(doc.LoadFile(dir_.file(name).c_str())) << name << ": " << doc.ErrorDesc();
    ASSERT_NE(doc.RootElement(), nullptr);
    EXPECT_EQ(std::string(doc.RootElement()->Value()), "svg");
  }
  test::TempDir dir_;
};

TEST_F(ExperimentSmoke, Fig6TracesEveryQPhaseStrategyAndTheErrorFalls) {
  const auto r = run("fig6");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("| lm-iter |"), std::string::npos) << r.out;
  const auto csv = readCsv(dir_.file("fig6.csv"));
  ASSERT_GT(csv.size(), 1u);
  const int method = column(csv[0], "q_phase"), it = column(csv[0], "iteration");
  const int err = column(csv[0], "mean_relative_error");
  const int rms = column(csv[0], "marker_rms_m");
  for (const std::string m : {"lm-batch", "lm-iter", "bfgs"}) {
    std::vector<double> e, x;
    for (size_t i = 1; i < csv.size(); ++i)
      if (csv[i][method] == m) {
        e.push_back(std::stod(csv[i][err]));
        x.push_back(std::stod(csv[i][rms]));
        EXPECT_EQ(std::stoi(csv[i][it]), static_cast<int>(e.size()) - 1);
      }
    ASSERT_EQ(e.size(), 5u) << m << ": the seed and 4 iterations";
    // From the zero seed the marker fit must improve a lot even in 4 steps.
    EXPECT_LT(x.back(), 0.5 * x.front()) << m;
  }
  expectSvg("fig6.svg");
}

TEST_F(ExperimentSmoke, Fig7GridHasEveryCellAndStacTracksAnEasySeed) {
  const auto r = run("fig7");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("STAC vs EKF"), std::string::npos) << r.out;
  const auto csv = readCsv(dir_.file("fig7.csv"));
  ASSERT_EQ(csv.size(), 5u) << "header + 2 x 2 grid";
  const int level = column(csv[0], "seeding_level"), noise = column(csv[0], "noise_scale");
  const int stac = column(csv[0], "stac_diverged"), ekf = column(csv[0], "ekf_diverged");
  const int stac_q = column(csv[0], "stac_angles_diverged_pct");
  for (size_t i = 1; i < csv.size(); ++i) {
    EXPECT_GE(std::stoi(csv[i][ekf]), 0);
    if (std::stod(csv[i][level]) < 0.5 && std::stod(csv[i][noise]) < 2) {
      // Small seeding error, nominal noise: nothing diverges.
      EXPECT_EQ(std::stoi(csv[i][stac]), 0) << test::readFile(dir_.file("fig7.csv"));
      EXPECT_EQ(std::stod(csv[i][stac_q]), 0.0);
    }
  }
  expectSvg("fig7.svg");
}

TEST_F(ExperimentSmoke, TablesPredictHeldOutFramesBetterAfterCalibration) {
  const auto r = run("tables");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("Table I analog"), std::string::npos) << r.out;
  const auto csv = readCsv(dir_.file("tables.csv"));
  ASSERT_GT(csv.size(), 1u);
  const int cal = column(csv[0], "calibration"), from = column(csv[0], "q_from");
  const int marker = column(csv[0], "marker_mae_m");
  double manual = -1, stac = -1, classical = -1;
  for (size_t i = 1; i < csv.size(); ++i) {
    if (csv[i][from] != "joint") continue;
    const double v = std::stod(csv[i][marker]);
    if (csv[i][cal] == "manual") manual = v;
    if (csv[i][cal] == "stac") stac = v;
    if (csv[i][cal] == "classical") classical = v;
  }
  ASSERT_GT(manual, 0);
  ASSERT_GT(stac, 0);
  ASSERT_GT(classical, 0);
  // Markers predicted from the pots on unseen frames: calibration must help
  // (the paper: STAC halves the manual error at least).
  EXPECT_LT(stac, 0.5 * manual);
  expectSvg("tables.svg");
}

TEST_F(ExperimentSmoke, BadArgumentsExitTwo) {
  auto r = test::runCommand(test::appPath("stac_experiment") + " --run fig9 --out " + dir_.file(""));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("fig6|fig7|tables|all"), std::string::npos) << r.err;
  r = test::runCommand(test::appPath("stac_experiment") + " --run fig6 --out " +
                       dir_.file("missing"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("missing"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace stac
