// Real data, as a user gets it (../shared/realdata/tiago: a TIAGo arm with a
// Qualisys body on its hand, FIGAROH's recording): the raw export,
// unmodified, calibrates with data/tiago_qualisys_sensors.yaml (a marker
// on x1,y1,z1, encoder gains held at 1, bookkeeping ignored); the same log
// with <marker>@<link> columns calibrates with no sensors file. Skipped
// when the recordings are not configured (STAC_REALDATA_DIR).
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "stac/log.hpp"
#include "stac/robot_model.hpp"
#include "stac/sensors_file.hpp"
#include "support/test_util.hpp"

namespace stac {
namespace {

std::string realdata(const std::string& name) {
  return std::string(STAC_REALDATA_DIR) + "/tiago/" + name;
}

bool haveRealdata() {
  return std::string(STAC_REALDATA_DIR) != "" &&
         std::ifstream(realdata("qualisys_2021-11-30_static_postures.csv")).good();
}

const char* kBookkeeping = "shipped_row,t_start_robot,t_end_robot,marker_std_mm";

class Tiago : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!haveRealdata()) GTEST_SKIP() << "no ../shared/realdata (STAC_REALDATA_DIR)";
  }
  test::CommandResult calib(const std::string& log, const std::string& args) const {
    return test::runCommand("timeout 120 " + test::appPath("stac_calib") + " --urdf " +
                            realdata("tiago_48_schunk.urdf") + " --log " + log + " --output " +
                            dir_.file("cal.yaml") + " --quiet " + args);
  }
  SensorsFile calibration() const {
    return loadSensorsFile(dir_.file("cal.yaml"),
                           RobotModel::fromFile(realdata("tiago_48_schunk.urdf")));
  }
  test::TempDir dir_;
};

// The fit's residual per marker, from the written calibration.
double markerRms(const std::string& yaml, const std::string& marker) {
  const size_t at = yaml.find("- name: " + marker);
  const size_t rms = yaml.find("residual: {rms: ", at);
  return std::stod(yaml.substr(rms + 16));
}

TEST_F(Tiago, RawExportCalibratesWithTheBundledSensorsFile) {
  const std::string log = realdata("qualisys_2021-11-30_static_postures.csv");
  const auto r = calib(log, "--sensors " + test::dataPath("tiago_qualisys_sensors.yaml"));
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  EXPECT_EQ(r.err, "");  // nothing from urdfdom either
  const std::string yaml = test::readFile(dir_.file("cal.yaml"));
  const SensorsFile cal = calibration();
  // It read x1,y1,z1 and the eight encoders, and every one of the 37 postures.
  ASSERT_EQ(cal.sensors.markers.size(), 1u);
  EXPECT_EQ(cal.sensors.markers[0].logColumns()[0], "x1");
  EXPECT_EQ(cal.sensors.joint_sensors.size(), 8u);
  EXPECT_NE(yaml.find("frames: 37"), std::string::npos) << yaml;
  EXPECT_NE(yaml.find("count: 37"), std::string::npos) << yaml;
  // A plausible result: the hand point fits to a few millimetres (FIGAROH
  // reaches 3.4 mm RMS held out with the same 14 parameters), the point
  // lies within a hand's reach of its link, the gains stayed at 1 and the
  // joint offsets are small.
  const double rms = markerRms(yaml, "hand_bl");
  EXPECT_GT(rms, 0.0005);
  EXPECT_LT(rms, 0.006) << yaml;
  EXPECT_LT(cal.theta.marker_position[0].norm(), 0.3);
  for (size_t j = 0; j < 8; ++j) {
    EXPECT_EQ(cal.theta.joint_sensor[j].gain, 1.0) << j;
    EXPECT_LT(std::abs(cal.theta.joint_sensor[j].bias), 0.1) << j;
  }
  EXPECT_LT(cal.theta.mocap.translation.norm(), 2.0);
  EXPECT_NE(yaml.find("unidentifiable: []"), std::string::npos) << yaml;
}

TEST_F(Tiago, AHalfFixedSensorsFreeBiasIsReportedWhenItIsAGauge) {
  // arm_1's gain held, its bias free: the bias trades off with the mocap
  // rotation about arm_1's vertical axis, and the report says so.
  std::string seed = test::readFile(test::dataPath("tiago_qualisys_sensors.yaml"));
  const std::string arm1 = "joint: arm_1_joint, gain: 1.0, bias: 0.0, sigma: 0.001, fixed: true";
  ASSERT_NE(seed.find(arm1), std::string::npos);
  seed.replace(seed.find(arm1) + arm1.size() - 4, 4, "[gain]");
  test::writeFile(dir_.file("half.yaml"), seed);
  const auto r = calib(realdata("qualisys_2021-11-30_static_postures.csv"),
                       "--sensors " + dir_.file("half.yaml"));
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  EXPECT_NE(r.out.find("bias of arm_1_joint trades off with the mocap rotation"),
            std::string::npos)
      << r.out;
  const std::string yaml = test::readFile(dir_.file("cal.yaml"));
  EXPECT_NE(yaml.find("joint_sensors.arm_1_joint.bias"), std::string::npos) << yaml;
  EXPECT_EQ(yaml.find("joint_sensors.arm_1_joint.gain"), std::string::npos) << yaml;
  const SensorsFile cal = calibration();
  EXPECT_EQ(cal.theta.joint_sensor[1].gain, 1.0);
}

TEST_F(Tiago, AtColumnsCalibrateWithNoSensorsFile) {
  // The header renamed: point 1 of the hand body is p1@wrist_ft_tool_link.
  // (Points 2-4 are virtual points of the same tracked body, exact to 1 µm:
  // as free markers they would fit the mocap to nothing and leave the
  // encoders every error, so they are ignored, as FIGAROH does.)
  std::string text = test::readFile(realdata("qualisys_2021-11-30_static_postures.csv"));
  const std::string from = "x1,y1,z1,";
  ASSERT_EQ(text.rfind(from, 0), 0u);
  text.replace(0, from.size(),
               "p1@wrist_ft_tool_link.x,p1@wrist_ft_tool_link.y,p1@wrist_ft_tool_link.z,");
  test::writeFile(dir_.file("renamed.csv"), text);
  const auto r = calib(dir_.file("renamed.csv"),
                       std::string("--ignore-columns x2,y2,z2,x3,y3,z3,x4,y4,z4,") + kBookkeeping);
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  const SensorsFile cal = calibration();
  ASSERT_EQ(cal.sensors.markers.size(), 1u);
  EXPECT_EQ(cal.sensors.markers[0].name, "p1");
  EXPECT_EQ(cal.sensors.markers[0].link_name, "wrist_ft_tool_link");
  EXPECT_EQ(cal.sensors.joint_sensors.size(), 8u);
  const std::string yaml = test::readFile(dir_.file("cal.yaml"));
  EXPECT_LT(markerRms(yaml, "p1"), 0.006) << yaml;
  // Every parameter free (gains too): the three freedoms the bundled
  // sensors file holds are named, not returned as numbers.
  for (const char* gauge :
       {"bias of arm_1_joint trades off with the mocap rotation",
        "bias of torso_lift_joint trades off with the mocap translation",
        "bias of arm_7_joint trades off with marker p1 position"})
    EXPECT_NE(r.out.find(gauge), std::string::npos) << gauge << " in\n" << r.out;
  EXPECT_LT((cal.theta.marker_position[0] - Eigen::Vector3d(0.063, -0.003, 0.07)).norm(), 0.03);
}

}  // namespace
}  // namespace stac
