// Real data, as a user gets it (../shared/realdata/tiago: a TIAGo arm with a
// Qualisys body on its hand, FIGAROH's recording): the raw export,
// unmodified, calibrates with data/tiago_qualisys_sensors.yaml (a marker
// on x1,y1,z1, encoder gains held at 1, bookkeeping ignored); the same log
// with <marker>@<link> columns calibrates with no sensors file (the
// bookkeeping given to --ignore-columns). Skipped
// when the recordings are not configured (STAC_REALDATA_DIR).
#include <gtest/gtest.h>

#include <fstream>
#include <string>
#include <vector>

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

  // The marker is point 1: the same file mapped onto point 2's columns
  // puts its marker as far from this one as the recorded points are apart.
  std::string seed = test::readFile(test::dataPath("tiago_qualisys_sensors.yaml"));
  seed.replace(seed.find("columns: [x1, y1, z1]"), 21, "columns: [x2, y2, z2]");
  seed.replace(seed.find("[x2, y2, z2, "), 13, "[x1, y1, z1, ");
  test::writeFile(dir_.file("p2.yaml"), seed);
  ASSERT_EQ(calib(log, "--sensors " + dir_.file("p2.yaml")).exit_code, 0);
  const Log raw = readLog(log);
  const Eigen::Vector3d p1 = raw.values.block<1, 3>(0, 0).transpose();
  const Eigen::Vector3d p2 = raw.values.block<1, 3>(0, 3).transpose();
  EXPECT_NEAR((calibration().theta.marker_position[0] - cal.theta.marker_position[0]).norm(),
              (p1 - p2).norm(), 0.002);
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
  // The header renamed: point k of the hand body is pk@wrist_ft_tool_link.
  const std::string raw = realdata("qualisys_2021-11-30_static_postures.csv");
  std::string text = test::readFile(raw);
  std::string header = text.substr(0, text.find('\n'));
  for (int k = 1; k <= 4; ++k)
    for (const char axis : {'x', 'y', 'z'}) {
      const std::string from = std::string(1, axis) + std::to_string(k) + ",";
      const std::string to = "p" + std::to_string(k) + "@wrist_ft_tool_link." + axis + ",";
      ASSERT_EQ(header.find(from), header.rfind(from));
      header.replace(header.find(from), from.size(), to);
    }
  test::writeFile(dir_.file("renamed.csv"), header + text.substr(text.find('\n')));
  const auto r = calib(dir_.file("renamed.csv"), std::string("--ignore-columns ") + kBookkeeping);
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  const SensorsFile cal = calibration();
  ASSERT_EQ(cal.sensors.markers.size(), 4u);
  for (int k = 0; k < 4; ++k) {
    EXPECT_EQ(cal.sensors.markers[k].name, "p" + std::to_string(k + 1));
    EXPECT_EQ(cal.sensors.markers[k].link_name, "wrist_ft_tool_link");
  }
  EXPECT_EQ(cal.sensors.joint_sensors.size(), 8u);
  const std::string yaml = test::readFile(dir_.file("cal.yaml"));
  for (int k = 1; k <= 4; ++k) EXPECT_LT(markerRms(yaml, "p" + std::to_string(k)), 0.003) << yaml;
  // Every parameter free (gains too): the freedoms the bundled sensors file
  // holds are named, not returned as numbers.
  for (const char* gauge : {"bias of arm_1_joint trades off with the mocap rotation",
                            "bias of torso_lift_joint trades off with the mocap translation",
                            "bias of arm_7_joint trades off with marker"})
    EXPECT_NE(r.out.find(gauge), std::string::npos) << gauge << " in\n" << r.out;
  // ... and each listed with its kind, for scripts: exact null directions.
  size_t listed = 0;
  for (size_t at = yaml.find("kind: "); at != std::string::npos; at = yaml.find("kind: ", at + 1)) {
    EXPECT_EQ(yaml.compare(at, 20, "kind: null_direction"), 0) << yaml.substr(at, 30);
    ++listed;
  }
  EXPECT_EQ(listed, 3u) << yaml;
  // The four fitted points keep the recorded body's shape (its mutual
  // distances, which no gauge changes) to a millimetre.
  const Log log = readLog(raw);
  auto recorded = [&](int k) {
    Eigen::Vector3d p;
    for (int i = 0; i < 3; ++i) p[i] = log.values(0, 3 * k + i);
    return p;
  };
  const std::vector<Eigen::Vector3d>& d = cal.theta.marker_position;
  for (int a = 0; a < 4; ++a)
    for (int b = a + 1; b < 4; ++b)
      EXPECT_NEAR((d[a] - d[b]).norm(), (recorded(a) - recorded(b)).norm(), 0.001) << a << b;
}

// Issue 13 on real data: the 5 interleaved folds of FIGAROH's evaluation
// (posture i held out in fold i mod 5), gains free. Each fit converges
// within 30 outer iterations and passes its own checks: with point 1 as the
// marker (it took 54-363 while a group's σ could drift towards 0), and with
// the four points of the hand's body as four markers and every arm joint's
// origin free (fold 3 took 38 while coupled steps waited for the
// alternation's decrease to fall below 1%; alternation.cpp).
class TiagoFolds : public Tiago {
 protected:
  // `suspect_because` empty: every fold passes its checks (exit 0, verdict
  // ok); else every fold fails them (exit 4) with a reason containing it.
  void expectEveryFoldConverges(int markers, const std::string& extra,
                                const std::string& suspect_because = "") {
    const std::string text = test::readFile(realdata("qualisys_2021-11-30_static_postures.csv"));
    std::vector<std::string> lines;
    for (size_t at = 0, end; at < text.size(); at = end + 1) {
      end = text.find('\n', at);
      if (end == std::string::npos) end = text.size();
      if (end > at) lines.push_back(text.substr(at, end - at));
    }
    ASSERT_EQ(lines.size(), 38u);  // header + 37 postures
    std::string seed = "mocap:\n  sigma: 0.001\n  markers:\n";
    std::string unused;
    for (int k = 1; k <= 4; ++k) {
      const std::string n = std::to_string(k);
      if (k <= markers)
        seed += "    - {name: p" + n + ", link: wrist_ft_tool_link, columns: [x" + n + ", y" + n +
                ", z" + n + "]}\n";
      else
        unused += "x" + n + ", y" + n + ", z" + n + ", ";
    }
    seed += "joint_sensors:\n";
    for (const char* j : kArmJoints)
      seed += std::string("  - {name: ") + j + ", joint: " + j + ", sigma: 0.001}\n";
    seed += "ignore_columns: [" + unused + std::string(kBookkeeping) + "]\n";
    test::writeFile(dir_.file("seed.yaml"), seed);
    for (int fold = 0; fold < 5; ++fold) {
      std::string train = lines[0] + "\n";
      for (size_t i = 1; i < lines.size(); ++i)
        if ((i - 1) % 5 != static_cast<size_t>(fold)) train += lines[i] + "\n";
      test::writeFile(dir_.file("train.csv"), train);
      const auto r = calib(dir_.file("train.csv"), "--sensors " + dir_.file("seed.yaml") + extra);
      ASSERT_EQ(r.exit_code, suspect_because.empty() ? 0 : 4) << "fold " << fold << ": " << r.err;
      const std::string yaml = test::readFile(dir_.file("cal.yaml"));
      EXPECT_NE(yaml.find("converged: true"), std::string::npos) << yaml;
      EXPECT_NE(yaml.find(suspect_because.empty() ? "verdict: ok" : suspect_because),
                std::string::npos) << yaml;
      const size_t at = yaml.find("iterations: ");
      ASSERT_NE(at, std::string::npos);
      EXPECT_LE(std::stoi(yaml.substr(at + 12)), 30) << "fold " << fold;
    }
  }

  static constexpr const char* kArmJoints[] = {"torso_lift_joint", "arm_1_joint", "arm_2_joint",
                                               "arm_3_joint",      "arm_4_joint", "arm_5_joint",
                                               "arm_6_joint",      "arm_7_joint"};
};

TEST_F(TiagoFolds, OnePointEveryFoldConvergesWithin30IterationsWithVerdictOk) {
  expectEveryFoldConverges(1, "");
}

TEST_F(TiagoFolds, FourPointsAndJointOriginsEveryFoldConvergesWithin30Iterations) {
  std::string origins;
  for (const char* j : kArmJoints) origins += std::string(origins.empty() ? "" : ",") + j;
  expectEveryFoldConverges(4, " --joint-origins " + origins);
}

// The four points as four markers without the joints' origins. They are
// virtual points of one tracked body (solve/marker_bodies.hpp): 12 rows a
// posture carry one pose error, which the 8 joints' angles can take whole.
// Counted as 12 independent rows (3 of them taken) the marker σ shrank to
// 0.37 mm, the joint readings' grew to 4.2x their seed, and every fold was
// suspect, with or without a robust loss (held-out error 4.1 mm). Counted as
// one pose: marker σ 0.64-0.72 mm, joint σ 2.3-2.9x its seed (the URDF's
// geometry does not explain the hand's orientation), 3.1 mm held out.
TEST_F(TiagoFolds, FourPointsOfOneBodyWithoutOriginsPassWithOrWithoutARobustLoss) {
  expectEveryFoldConverges(4, "");
  expectEveryFoldConverges(4, " --loss huber");
}

}  // namespace
}  // namespace stac
