// stac_calib --method ekf|classical end to end: the same output schema as
// STAC, --joint-angles, --ekf-initial-q and its validation, and the
// classical method's refusal of joints without a one-joint sensor.
#include <gtest/gtest.h>

#include <cmath>

#include "stac/log.hpp"
#include "stac/robot_model.hpp"
#include "stac/sensors_file.hpp"
#include "support/arm_files.hpp"
#include "support/test_util.hpp"

namespace stac {
namespace {

// The arm's truth with every free value moved a little: a manual calibration.
std::string nearSeedYaml(const RobotModel& robot, const std::string& truth_path) {
  SensorsFile f = loadSensorsFile(truth_path, robot);
  f.theta.mocap.rotation =
      Eigen::Quaterniond(Eigen::AngleAxisd(0.04, Eigen::Vector3d(1, 2, 3).normalized())) *
      f.theta.mocap.rotation;
  f.theta.mocap.translation += Eigen::Vector3d(0.01, -0.01, 0.01);
  for (size_t m = 0; m < f.sensors.markers.size(); ++m)
    if (!f.sensors.markers[m].fixed)
      f.theta.marker_position[m] += Eigen::Vector3d(0.005, 0, -0.005);
  for (GainBias& gb : f.theta.joint_sensor) gb.gain *= 1.08, gb.bias += 0.04;
  for (GainBias& gb : f.theta.tendon_sensor) gb.gain *= 0.93, gb.bias += 0.05;
  return sensorsToYaml(f.sensors, f.theta);
}

class BaselinesCli : public ::testing::Test {
 protected:
  void SetUp() override {
    test::writeFile(file("arm.urdf"), test::kArmUrdf);
    test::writeFile(file("truth.yaml"), test::kArmTruth);
    const RobotModel robot = RobotModel::fromFile(file("arm.urdf"));
    test::writeFile(file("near.yaml"), nearSeedYaml(robot, file("truth.yaml")));
    const auto r = test::runCommand(test::appPath("stac_simulate") + " --urdf " + file("arm.urdf") +
                                    " --sensors " + file("truth.yaml") +
                                    " --frames 300 --noise-scale 0.2 --log " + file("data.csv") +
                                    " --joint-angles " + file("q_true.csv") + " --seed 4");
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  std::string file(const std::string& n) const { return dir_.file(n); }
  test::CommandResult calib(const std::string& extra) const {
    return test::runCommand(test::appPath("stac_calib") + " --urdf " + file("arm.urdf") + " " +
                            extra);
  }
  test::TempDir dir_;
};

TEST_F(BaselinesCli, EkfWritesTheCalibrationSchemaAndFilteredAngles) {
  const auto r = calib("--log " + file("data.csv") + " --sensors " + file("near.yaml") +
                       " --method ekf --ekf-initial-q " + file("q_true.csv") + " --output " +
                       file("cal.yaml") + " --joint-angles " + file("q.csv"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // One progress line per 10% of the frames.
  int lines = 0;
  for (size_t at = 0; (at = r.err.find("ekf ", at)) != std::string::npos; ++at) ++lines;
  EXPECT_EQ(lines, 10) << r.err;
  EXPECT_NE(r.out.find("method ekf"), std::string::npos) << r.out;
  const std::string yaml = test::readFile(file("cal.yaml"));
  EXPECT_NE(yaml.find("method: ekf"), std::string::npos);
  EXPECT_NE(yaml.find("std:"), std::string::npos);
  EXPECT_NE(yaml.find("residual:"), std::string::npos);
  // It reads back as a seed, and the filtered q follows the truth.
  const RobotModel robot = RobotModel::fromFile(file("arm.urdf"));
  const SensorsFile cal = loadSensorsFile(file("cal.yaml"), robot);
  EXPECT_NEAR(cal.theta.joint_sensor[1].gain, 2.1, 0.03);
  const Log q = readLog(file("q.csv")), q_true = readLog(file("q_true.csv"));
  ASSERT_EQ(q.columns, (std::vector<std::string>{"j1", "j2", "j3", "j4"}));
  ASSERT_EQ(q.numFrames(), 300);
  EXPECT_LT((q.values.bottomRows(100) - q_true.values.bottomRows(100)).cwiseAbs().maxCoeff(), 0.03);
}

TEST_F(BaselinesCli, ClassicalWritesTheCalibrationSchemaAndAnglesFromThePots) {
  const auto r = calib("--log " + file("data.csv") + " --sensors " + file("near.yaml") +
                       " --method classical --output " + file("cal.yaml") + " --joint-angles " +
                       file("q.csv"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("classical"), std::string::npos) << "progress per iteration: " << r.err;
  EXPECT_NE(r.out.find("unidentifiable: none"), std::string::npos) << r.out;
  const std::string yaml = test::readFile(file("cal.yaml"));
  EXPECT_NE(yaml.find("method: classical"), std::string::npos);
  const RobotModel robot = RobotModel::fromFile(file("arm.urdf"));
  const SensorsFile cal = loadSensorsFile(file("cal.yaml"), robot);
  EXPECT_NEAR(cal.theta.joint_sensor[1].gain, 2.1, 0.02);
  EXPECT_NEAR(cal.theta.tendon_sensor[0].gain, 30.0, 0.3);
  const Log q = readLog(file("q.csv")), q_true = readLog(file("q_true.csv"));
  ASSERT_EQ(q.numFrames(), 300);
  EXPECT_LT((q.values - q_true.values).cwiseAbs().maxCoeff(), 0.03);
}

// Two cylinders and markers but no pots: every joint is uncovered.
TEST_F(BaselinesCli, ClassicalRefusesJointsWithoutAJointSensor) {
  std::string truth = test::kArmTruth;
  const size_t begin = truth.find("joint_sensors:"), end = truth.find("tendon_sensors:");
  truth.replace(begin, end - begin, "joint_sensors: []\n");
  test::writeFile(file("tendon_truth.yaml"), truth);
  auto r = test::runCommand(test::appPath("stac_simulate") + " --urdf " + file("arm.urdf") +
                            " --sensors " + file("tendon_truth.yaml") + " --frames 50 --log " +
                            file("tendon.csv"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto before = dir_.list();
  r = calib("--log " + file("tendon.csv") + " --sensors " + file("tendon_truth.yaml") +
            " --method classical --output " + file("out.yaml"));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find(file("tendon_truth.yaml")), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("j1, j2, j3, j4"), std::string::npos) << r.err;
  EXPECT_EQ(dir_.list(), before) << "an output file was left behind";
  // STAC itself takes the same robot.
  r = calib("--log " + file("tendon.csv") + " --sensors " + file("tendon_truth.yaml") +
            " --output " + file("out.yaml") + " --quiet --max-iterations 3");
  // Three iterations need not converge: written either way (0, or 4 with
  // "not converged" in the verdict), never refused.
  EXPECT_TRUE(r.exit_code == 0 || r.exit_code == 4) << r.err;
  EXPECT_FALSE(test::readFile(file("out.yaml")).empty());
}

TEST_F(BaselinesCli, EkfInitialQWithAWrongColumn) {
  test::writeFile(file("q0.csv"), "time,j1,j2,j3,elbow\n0,0.1,0.2,0.3,0.4\n");
  const auto before = dir_.list();
  auto r = calib("--log " + file("data.csv") + " --sensors " + file("near.yaml") +
                 " --method ekf --ekf-initial-q " + file("q0.csv") + " --output " +
                 file("out.yaml"));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find(file("q0.csv") + ":1"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("'elbow'"), std::string::npos) << r.err;
  test::writeFile(file("q1.csv"), "j1,j2,j3,j4\n0.1,0.2,,0.4\n");
  r = calib("--log " + file("data.csv") + " --sensors " + file("near.yaml") +
            " --method ekf --ekf-initial-q " + file("q1.csv") + " --output " + file("out.yaml"));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find(file("q1.csv") + ":2"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("j3"), std::string::npos) << r.err;
  EXPECT_EQ(dir_.list().size(), before.size() + 1);  // q1.csv, no output
}

TEST_F(BaselinesCli, UsageErrors) {
  auto r = calib("--log " + file("data.csv") + " --method fast");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("stac|joint|ekf|classical"), std::string::npos) << r.err;
  r = calib("--log " + file("data.csv") + " --ekf-initial-q " + file("q_true.csv"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("needs --method ekf"), std::string::npos) << r.err;
  r = calib("--log " + file("data.csv") + " --method ekf --ekf-q-speed -1");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("speed"), std::string::npos) << r.err;
  r = test::runCommand(test::appPath("stac_calib") + " --help");
  EXPECT_NE(r.out.find("--ekf-initial-q"), std::string::npos);
  EXPECT_NE(r.out.find("classical"), std::string::npos);
}

}  // namespace
}  // namespace stac
