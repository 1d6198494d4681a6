// stac_export_header end to end: the generated header compiles as strict C99
// (gcc -std=c99 -Wall -Wextra -Werror -pedantic), and a C program using it
// converts raw readings to the same joint angles, lengths and constants as
// the library computes from the loaded sensors file.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <sstream>
#include <string>

#include "stac/robot_model.hpp"
#include "stac/sensors_file.hpp"
#include "support/arm_files.hpp"
#include "support/test_util.hpp"

namespace stac {
namespace {

using test::runCommand;
using test::TempDir;

// Names that need sanitising, a prismatic joint, a mimic follower and a
// coupling tendon.
const char* kOddUrdf = R"(<robot name="odd">
  <link name="base"/><link name="l1"/><link name="l2"/><link name="l3"/>
  <joint name="slide-1" type="prismatic"><parent link="base"/><child link="l1"/>
    <axis xyz="1 0 0"/><limit lower="0" upper="0.2" effort="1" velocity="1"/></joint>
  <joint name="hinge" type="revolute"><parent link="l1"/><child link="l2"/>
    <origin xyz="0.1 0 0"/><axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  <joint name="follower" type="revolute"><parent link="l2"/><child link="l3"/>
    <origin xyz="0.1 0 0"/><axis xyz="0 0 1"/><limit lower="-2" upper="2" effort="1" velocity="1"/>
    <mimic joint="hinge" multiplier="2.0" offset="0.1"/></joint>
</robot>
)";

const char* kOddSensors = R"(mocap:
  frame:
    translation: [1.0e-05, -2.5, 3.0]
    quaternion: [0.5, 0.5, -0.5, 0.5]
  markers:
    - {name: tip.0, link: l3, position: [0.1, -0.0, 0.3333333333333333]}
joint_sensors:
  - {name: slide.pot, joint: slide-1, gain: 1234.5, bias: -17.25}
  - {name: 2nd-enc, joint: follower, gain: -651.8986469044033, bias: 2048.0}
tendon_sensors:
  - name: flex/tendon
    gain: 0.001
    bias: 0.1
    coupling: {hinge: 0.009, follower: -0.012}
)";

class FirmwareHeader : public ::testing::Test {
 protected:
  void SetUp() override {
    if (runCommand("gcc --version").exit_code != 0) GTEST_SKIP() << "no gcc";
  }

  // Writes the URDF and sensors files, runs the app; returns its result.
  test::CommandResult exportHeader(const char* urdf, const char* sensors) {
    test::writeFile(dir_.file("robot.urdf"), urdf);
    test::writeFile(dir_.file("calibration.yaml"), sensors);
    return runCommand("'" + test::appPath("stac_export_header") + "' --sensors '" +
                      dir_.file("calibration.yaml") + "' --urdf '" + dir_.file("robot.urdf") +
                      "' --output '" + dir_.file("calibration.h") + "'");
  }

  // Compiles `body` (the statements of main) against the header, strict C99,
  // runs it and returns "key value" lines as a map.
  std::map<std::string, double> compileAndRun(const std::string& body) {
    const std::string c_file = dir_.file("main.c"), exe = dir_.file("main");
    test::writeFile(c_file,
                    "#include <stdio.h>\n"
                    "#include \"calibration.h\"\n"
                    "#include \"calibration.h\" /* the include guard */\n"
                    "#define OUT(name, value) printf(\"%s %.17g\\n\", name, (double)(value))\n"
                    "int main(void) {\n" +
                        body + "  return 0;\n}\n");
    const test::CommandResult cc =
        runCommand("gcc -std=c99 -Wall -Wextra -Werror -pedantic -o '" + exe + "' '" + c_file +
                   "'");
    EXPECT_EQ(cc.exit_code, 0) << cc.err << "\n" << test::readFile(dir_.file("calibration.h"));
    const test::CommandResult run = runCommand("'" + exe + "'");
    EXPECT_EQ(run.exit_code, 0) << run.err;
    std::map<std::string, double> values;
    std::istringstream in(run.out);
    std::string key;
    double v;
    while (in >> key >> v) values[key] = v;
    return values;
  }

  TempDir dir_;
};

TEST_F(FirmwareHeader, ArmConversionsMatchTheLibrary) {
  const test::CommandResult r = exportHeader(test::kArmUrdf, test::kArmTruth);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string text = test::readFile(dir_.file("calibration.h"));
  EXPECT_NE(text.find("#ifndef STAC_CALIBRATION_H"), std::string::npos);
  EXPECT_EQ(text.find("math.h"), std::string::npos) << "nothing in it needs <math.h>";

  const RobotModel robot = RobotModel::fromFile(dir_.file("robot.urdf"));
  const SensorsFile file = loadSensorsFile(dir_.file("calibration.yaml"), robot);
  const double raws[] = {-3.0, -0.25, 0.0, 0.4, 1.7, 1234.5};

  std::string body;
  for (const JointSensorConfig& s : file.sensors.joint_sensors)  // j1_pot ... j4_pot
    for (int k = 0; k < 6; ++k)
      body += "  OUT(\"" + s.name + "@" + std::to_string(k) + "\", stac_" + s.name +
              "_to_radians(" + std::to_string(raws[k]) + "));\n";
  body +=
      "  { const double d[3] = STAC_M_L2A_POSITION; OUT(\"m_l2a.x\", d[0]);"
      " OUT(\"m_l2a.y\", d[1]); OUT(\"m_l2a.z\", d[2]); }\n"
      "  { const double q[4] = STAC_MOCAP_QUATERNION; OUT(\"qw\", q[0]); OUT(\"qx\", q[1]);"
      " OUT(\"qy\", q[2]); OUT(\"qz\", q[3]); }\n"
      "  { const double t[3] = STAC_MOCAP_TRANSLATION; OUT(\"tx\", t[0]); OUT(\"ty\", t[1]);"
      " OUT(\"tz\", t[2]); }\n"
      "  OUT(\"cyl.len\", stac_cyl_to_length(2.0));\n"
      "  OUT(\"cyl.raw\", stac_cyl_from_length(0.05));\n"
      "  OUT(\"j2.gain\", STAC_J2_POT_GAIN); OUT(\"j2.bias\", STAC_J2_POT_BIAS);\n"
      "  OUT(\"counts\", STAC_NUM_JOINT_SENSORS * 100 + STAC_NUM_TENDON_SENSORS * 10"
      " + STAC_NUM_MARKERS);\n";
  const std::map<std::string, double> got = compileAndRun(body);

  for (std::size_t i = 0; i < file.sensors.joint_sensors.size(); ++i) {
    const GainBias& gb = file.theta.joint_sensor[i];
    for (int k = 0; k < 6; ++k) {
      const std::string key = file.sensors.joint_sensors[i].name + "@" + std::to_string(k);
      ASSERT_EQ(got.count(key), 1u) << key;
      EXPECT_DOUBLE_EQ(got.at(key), (raws[k] - gb.bias) / gb.gain) << key;
    }
  }
  // Constants are written exactly (shortest round trip).
  EXPECT_EQ(got.at("m_l2a.x"), file.theta.marker_position[1].x());
  EXPECT_EQ(got.at("m_l2a.y"), file.theta.marker_position[1].y());
  EXPECT_EQ(got.at("m_l2a.z"), file.theta.marker_position[1].z());
  const Eigen::Quaterniond& q = file.theta.mocap.rotation;
  EXPECT_EQ(got.at("qw"), q.w());
  EXPECT_EQ(got.at("qx"), q.x());
  EXPECT_EQ(got.at("qy"), q.y());
  EXPECT_EQ(got.at("qz"), q.z());
  EXPECT_EQ(got.at("tx"), file.theta.mocap.translation.x());
  EXPECT_EQ(got.at("ty"), file.theta.mocap.translation.y());
  EXPECT_EQ(got.at("tz"), file.theta.mocap.translation.z());
  EXPECT_EQ(got.at("j2.gain"), file.theta.joint_sensor[1].gain);
  EXPECT_EQ(got.at("j2.bias"), file.theta.joint_sensor[1].bias);
  const GainBias& cyl = file.theta.tendon_sensor[0];
  EXPECT_DOUBLE_EQ(got.at("cyl.len"), (2.0 - cyl.bias) / cyl.gain);
  EXPECT_DOUBLE_EQ(got.at("cyl.raw"), cyl.gain * 0.05 + cyl.bias);
  EXPECT_EQ(got.at("counts"), 4 * 100 + 1 * 10 + 5);
}

TEST_F(FirmwareHeader, SanitisedNamesPrismaticMimicAndCoupling) {
  const test::CommandResult r = exportHeader(kOddUrdf, kOddSensors);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const RobotModel robot = RobotModel::fromFile(dir_.file("robot.urdf"));
  const SensorsFile file = loadSensorsFile(dir_.file("calibration.yaml"), robot);

  const std::map<std::string, double> got = compileAndRun(
      "  OUT(\"slide\", stac_slide_pot_to_metres(100.0));\n"
      "  OUT(\"enc\", stac_2nd_enc_to_radians(1000.0));\n"
      "  OUT(\"enc.raw\", stac_2nd_enc_from_radians(0.5));\n"
      "  OUT(\"flex\", stac_flex_tendon_to_length(0.2));\n"
      "  OUT(\"c.hinge\", STAC_FLEX_TENDON_COUPLING_HINGE);\n"
      "  OUT(\"c.follower\", STAC_FLEX_TENDON_COUPLING_FOLLOWER);\n"
      "  OUT(\"tip.z\", STAC_TIP_0_Z); OUT(\"tip.y\", STAC_TIP_0_Y);\n"
      "  OUT(\"tx\", STAC_MOCAP_TX); OUT(\"qy\", STAC_MOCAP_QY);\n"
      "  OUT(\"names\", sizeof STAC_SLIDE_POT_JOINT + sizeof STAC_TIP_0_LINK);\n");

  const GainBias& slide = file.theta.joint_sensor[0];
  const GainBias& enc = file.theta.joint_sensor[1];
  const GainBias& flex = file.theta.tendon_sensor[0];
  EXPECT_DOUBLE_EQ(got.at("slide"), (100.0 - slide.bias) / slide.gain);
  EXPECT_DOUBLE_EQ(got.at("enc"), (1000.0 - enc.bias) / enc.gain);
  EXPECT_DOUBLE_EQ(got.at("enc.raw"), enc.gain * 0.5 + enc.bias);
  EXPECT_DOUBLE_EQ(got.at("flex"), (0.2 - flex.bias) / flex.gain);
  EXPECT_EQ(got.at("c.hinge"), 0.009);
  EXPECT_EQ(got.at("c.follower"), -0.012);
  EXPECT_EQ(got.at("tip.z"), file.theta.marker_position[0].z());
  EXPECT_EQ(got.at("tx"), file.theta.mocap.translation.x());
  EXPECT_EQ(got.at("qy"), file.theta.mocap.rotation.y());
  EXPECT_EQ(got.at("names"), sizeof "slide-1" + sizeof "l3");
  // -0.0 stays a double literal (and a parenthesised one).
  EXPECT_NE(test::readFile(dir_.file("calibration.h")).find("#define STAC_TIP_0_Y (-0.0)"),
            std::string::npos);
}

TEST_F(FirmwareHeader, ClashingIdentifiersAreAnError) {
  const test::CommandResult r = exportHeader(test::kArmUrdf, R"(joint_sensors:
  - {name: j1.pot, joint: j1}
  - {name: J1_POT, joint: j2}
)");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("STAC_J1_POT_"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("j1.pot"), std::string::npos) << r.err;
  EXPECT_EQ(dir_.list(), (std::vector<std::string>{"calibration.yaml", "robot.urdf"}));
}

TEST_F(FirmwareHeader, BadUsageAndBadInputExitTwo) {
  test::writeFile(dir_.file("robot.urdf"), test::kArmUrdf);
  test::writeFile(dir_.file("calibration.yaml"), "joint_sensors:\n  - {name: p, joint: nope}\n");
  const std::string app = "'" + test::appPath("stac_export_header") + "'";
  const std::string in = " --urdf '" + dir_.file("robot.urdf") + "' --sensors '" +
                         dir_.file("calibration.yaml") + "'";
  EXPECT_EQ(runCommand(app + in).exit_code, 2);  // no --output
  EXPECT_EQ(runCommand(app + in + " --output '" + dir_.file("robot.urdf") + "'").exit_code, 2);
  const test::CommandResult bad = runCommand(app + in + " --output '" + dir_.file("c.h") + "'");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("calibration.yaml:2"), std::string::npos) << bad.err;
  EXPECT_EQ(runCommand(app + " --help").exit_code, 0);
  EXPECT_EQ(dir_.list(), (std::vector<std::string>{"calibration.yaml", "robot.urdf"}));
}

}  // namespace
}  // namespace stac
