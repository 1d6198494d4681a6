// Log columns end to end (SPEC §3, §4): a seed that maps renamed columns
// (`column:`, `columns:`) and ignores bookkeeping (`ignore_columns:`,
// --ignore-columns) calibrates, is written back with every key and, fed
// back, gives the same calibration; each new error exits 2 with its message.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "stac/log.hpp"
#include "stac/measurement.hpp"
#include "stac/robot_model.hpp"
#include "stac/sensors_file.hpp"
#include "stac/simulate.hpp"
#include "support/arm_files.hpp"
#include "support/test_util.hpp"

namespace stac {
namespace {

// kArmSeed with j1_pot, m_l2a and cyl reading renamed columns, j1_pot's
// bias held at its true value (its gain free), and two bookkeeping columns.
const char* kMappedSeed = R"(mocap:
  sigma: 0.002
  markers:
    - {name: m_base, link: base, position: [0.05, 0.03, 0.0], fixed: true}
    - {name: m_l2a, link: l2, columns: [x1, y1, z1]}
    - {name: m_l2b, link: l2}
    - {name: m_l4a, link: l4, position: [0.04, 0.03, 0.02], fixed: true}
    - {name: m_l4b, link: l4}
joint_sensors:
  - {name: j1_pot, joint: j1, column: enc1, bias: 0.4, fixed: [bias]}
  - {name: j2_pot, joint: j2}
  - {name: j3_pot, joint: j3}
  - {name: j4_pot, joint: j4}
tendon_sensors:
  - name: cyl
    column: cyl_length
    path:
      - {link: l1, point: [0.03, 0.02, 0.0]}
      - {link: l3, point: [0.05, 0.0, 0.03]}
ignore_columns: [sample_id]
)";

class ColumnsCli : public ::testing::Test {
 protected:
  void SetUp() override {
    test::writeFile(file("arm.urdf"), test::kArmUrdf);
    test::writeFile(file("seed.yaml"), kMappedSeed);
    const RobotModel robot = RobotModel::fromString(test::kArmUrdf, "arm4");
    const SensorsFile sf = parseSensorsYaml(test::kArmTruth, "truth", robot);
    SimulationOptions so;
    so.frames = 60;
    so.seed = 11;
    Log log = simulate(MeasurementModel(robot, sf.sensors), sf.theta, so).data.log;
    // The columns as a recording system would name them, and two more.
    for (std::string& c : log.columns) {
      if (c == "j1_pot") c = "enc1";
      if (c == "cyl") c = "cyl_length";
      if (c.rfind("m_l2a.", 0) == 0) c = std::string(1, c.back()) + "1";
    }
    log.columns.push_back("sample_id");
    log.columns.push_back("operator");
    log.values.conservativeResize(Eigen::NoChange, log.values.cols() + 2);
    log.values.rightCols(2).setOnes();
    writeLog(file("data.csv"), log);
  }
  std::string file(const std::string& n) const { return dir_.file(n); }
  test::CommandResult calib(const std::string& args) const {
    return test::runCommand("timeout 60 " + test::appPath("stac_calib") + " --urdf " +
                            file("arm.urdf") + " --log " + file("data.csv") + " --quiet " + args);
  }
  void expectExit2(const test::CommandResult& r, const std::string& message) const {
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_NE(r.err.find(message), std::string::npos) << r.err;
  }
  test::TempDir dir_;
};

double gainIn(const SensorsFile& f, int sensor) { return f.theta.joint_sensor[sensor].gain; }

TEST_F(ColumnsCli, MappedSeedCalibratesAndFeedsBackToTheSameCalibration) {
  const auto a = calib("--sensors " + file("seed.yaml") + " --output " + file("a.yaml") +
                       " --ignore-columns operator");
  ASSERT_EQ(a.exit_code, 0) << a.err;
  const std::string ya = test::readFile(file("a.yaml"));
  for (const char* key : {"column: enc1", "columns: [x1, y1, z1]", "column: cyl_length",
                          "ignore_columns: [sample_id, operator]", "fixed: [bias]"})
    EXPECT_NE(ya.find(key), std::string::npos) << key << " in\n" << ya;
  const RobotModel robot = RobotModel::fromString(test::kArmUrdf, "arm4");
  const SensorsFile fa = loadSensorsFile(file("a.yaml"), robot);
  EXPECT_NEAR(gainIn(fa, 0), -1.5, 0.05);  // read from enc1, not from another column
  EXPECT_EQ(fa.theta.joint_sensor[0].bias, 0.4);
  EXPECT_NEAR(fa.theta.tendon_sensor[0].gain, 30.0, 1.0);

  // Fed back with no --ignore-columns: the file now ignores both. The same
  // calibration up to the solver's reach: the fed-back σ seeds (the first
  // run's adapted σ) weigh in the σ prior, which moves the optimum by ~1e-4.
  const auto b = calib("--sensors " + file("a.yaml") + " --output " + file("b.yaml"));
  ASSERT_EQ(b.exit_code, 0) << b.err;
  const SensorsFile fb = loadSensorsFile(file("b.yaml"), robot);
  EXPECT_EQ(fb.sensors.ignore_columns, fa.sensors.ignore_columns);
  for (int j = 0; j < 4; ++j) {
    EXPECT_NEAR(gainIn(fb, j), gainIn(fa, j), 1e-3) << j;
    EXPECT_NEAR(fb.theta.joint_sensor[j].bias, fa.theta.joint_sensor[j].bias, 1e-3) << j;
  }
  EXPECT_LT((fb.theta.marker_position[1] - fa.theta.marker_position[1]).norm(), 1e-4);
  EXPECT_NEAR(fb.theta.tendon_sensor[0].gain, fa.theta.tendon_sensor[0].gain, 1e-2);

  // stac_eval reads the same columns.
  const auto e = test::runCommand(test::appPath("stac_eval") + " --urdf " + file("arm.urdf") +
                                  " --sensors " + file("b.yaml") + " --log " + file("data.csv") +
                                  " --use joint,tendon");
  EXPECT_EQ(e.exit_code, 0) << e.err;
}

TEST_F(ColumnsCli, UnknownColumnInColumnKey) {
  std::string seed = kMappedSeed;
  seed.replace(seed.find("column: enc1"), 12, "column: enc7");
  test::writeFile(file("bad.yaml"), seed);
  expectExit2(calib("--sensors " + file("bad.yaml") + " --ignore-columns operator"),
              "stac_calib: error: " + file("bad.yaml") +
                  ":10: key 'joint_sensors[0].column': the log " + file("data.csv") +
                  " has no column 'enc7'; did you mean 'enc1'?");
}

TEST_F(ColumnsCli, ColumnBothMappedAndIgnored) {
  std::string seed = kMappedSeed;
  seed.replace(seed.find("[sample_id]"), 11, "[sample_id, x1]");
  test::writeFile(file("bad.yaml"), seed);
  expectExit2(calib("--sensors " + file("bad.yaml")),
              "stac_calib: error: " + file("bad.yaml") +
                  ":20: key 'ignore_columns[1]': column 'x1' is read by "
                  "mocap.markers[1].columns[0] (line 5): a column is a sensor's or ignored, "
                  "not both");
  // From the command line, in both apps that read a log.
  const std::string cli_message = file("seed.yaml") +
                                  ": --ignore-columns lists column 'enc1', which key "
                                  "'joint_sensors[0].column' (line 10) reads";
  expectExit2(calib("--sensors " + file("seed.yaml") + " --ignore-columns operator,enc1"),
              "stac_calib: error: " + cli_message);
  expectExit2(test::runCommand(test::appPath("stac_eval") + " --urdf " + file("arm.urdf") +
                               " --sensors " + file("seed.yaml") + " --log " + file("data.csv") +
                               " --use joint --ignore-columns enc1"),
              "stac_eval: error: " + cli_message);
  expectExit2(calib("--sensors " + file("seed.yaml") + " --ignore-columns operator,,x"),
              "stac_calib: error: --ignore-columns operator,,x: an empty column name");
}

TEST_F(ColumnsCli, BookkeepingColumnNotIgnored) {
  expectExit2(calib("--sensors " + file("seed.yaml")),
              "column(s) operator belong to no sensor in " + file("seed.yaml") +
                  " (list bookkeeping columns in ignore_columns)");
}

TEST_F(ColumnsCli, AtColumnOnAnUnknownLink) {
  test::writeFile(file("at.csv"),
                  "j1,j2,j3,j4,p@l4.x,p@l4.y,p@l4.z,q@l_4.x,q@l_4.y,q@l_4.z\n"
                  "0,0,0,0,0,0,0,0,0,0\n");
  const auto r = test::runCommand(test::appPath("stac_calib") + " --urdf " + file("arm.urdf") +
                                  " --log " + file("at.csv") + " --output " + file("o.yaml"));
  expectExit2(r, "stac_calib: error: " + file("at.csv") + ":1: 3 column(s) name no movable joint");
  EXPECT_NE(r.err.find("q@l_4.x (no link 'l_4' in " + file("arm.urdf") +
                       "; did you mean 'q@l4.x'?)"),
            std::string::npos)
      << r.err;
}

}  // namespace
}  // namespace stac
