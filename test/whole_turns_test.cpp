// The q-phase's whole-turn step (src/solve/whole_turns.hpp): a frame whose
// continuous joint sits a turn away from what its pot reads is moved back
// by that turn when that lowers the frame's cost, under any loss; a joint
// whose limits leave no room for a turn, a frozen one, or a frame whose pot
// reading is missing is not.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "stac/sensors_file.hpp"
#include "solve/q_phase.hpp"
#include "solve/whole_turns.hpp"

namespace stac {
namespace {

// j1 revolute within ±1.5; j2 continuous; j3 revolute within ±4 (more than
// a turn).
const char* kRobot = R"(<robot name="wrist">
  <link name="base"/><link name="a"/><link name="b"/><link name="c"/>
  <joint name="j1" type="revolute"><parent link="base"/><child link="a"/>
    <origin xyz="0 0 0.1"/><axis xyz="0 0 1"/>
    <limit lower="-1.5" upper="1.5" effort="1" velocity="1"/></joint>
  <joint name="j2" type="continuous"><parent link="a"/><child link="b"/>
    <origin xyz="0.2 0 0"/><axis xyz="0 1 0"/></joint>
  <joint name="j3" type="revolute"><parent link="b"/><child link="c"/>
    <origin xyz="0.1 0 0.05"/><axis xyz="1 0 0"/>
    <limit lower="-4" upper="4" effort="1" velocity="1"/></joint>
</robot>)";

const char* kSensors = R"(mocap:
  sigma: 0.002
  markers:
    - {name: m_a, link: a, position: [0.1, 0.02, 0.03]}
    - {name: m_b, link: b, position: [0.05, 0.04, 0.06]}
    - {name: m_c, link: c, position: [0.04, 0.05, 0.07]}
joint_sensors:
  - {name: p1, joint: j1, gain: 1.3, bias: 0.2, sigma: 0.01}
  - {name: p2, joint: j2, gain: -2.0, bias: 0.3, sigma: 0.01}
  - {name: p3, joint: j3, gain: 0.8, bias: -0.1, sigma: 0.01}
)";

struct Frame {
  RobotModel robot = RobotModel::fromString(kRobot, "wrist");
  SensorsFile file = parseSensorsYaml(kSensors, "test", robot);
  MeasurementModel model{robot, file.sensors};
  NoiseModel noise = NoiseModel::fromSeeds(file.sensors);
  Observations obs;
  Eigen::VectorXd q_true = Eigen::Vector3d(0.4, 1.1, -2.5);

  // One frame of noise-free readings at q_true.
  Frame() {
    obs.num_frames = 1;
    obs.marker.resize(1, 9);
    obs.joint.resize(1, 3);
    obs.tendon.resize(1, 0);
    KinematicsWorkspace kin(robot);
    predictFrame(model, file.theta, q_true, &kin, obs.marker.data(), obs.joint.data(), nullptr);
  }

  // q after a q-phase that starts at q_true + `offset`.
  Eigen::VectorXd solvedFrom(const Eigen::Vector3d& offset, const RobustLoss& loss,
                             std::vector<bool> frozen = {}) {
    QPhaseOptions options;
    options.method = QPhaseMethod::kLmBatch;
    options.threads = 1;
    options.frozen = std::move(frozen);
    options.whole_turns = true;
    std::vector<FrameWorkspace> ws(1, FrameWorkspace(model));
    QState state;
    state.q = (q_true + offset).transpose();
    qPhase(model, file.theta, noise, loss, obs, options, &ws, &state);
    return state.q.row(0).transpose();
  }
};

const Eigen::Vector3d kTurnOnJ2(0, 2 * M_PI, 0);

TEST(WholeTurns, AContinuousJointATurnOffComesBackUnderEveryLoss) {
  Frame f;
  for (LossKind kind : {LossKind::kNone, LossKind::kHuber, LossKind::kCauchy}) {
    const Eigen::VectorXd q = f.solvedFrom(kTurnOnJ2, RobustLoss(kind));
    EXPECT_LT((q - f.q_true).norm(), 1e-6) << static_cast<int>(kind) << " " << q.transpose();
  }
}

TEST(WholeTurns, TwoTurnsOffComeBackAndAJointWithLimitsOverATurnToo) {
  Frame f;
  // j2 two turns off; j3 a turn up, at 3.78 within its widened limits ±4.4.
  const Eigen::VectorXd q =
      f.solvedFrom(Eigen::Vector3d(0, -4 * M_PI, 2 * M_PI), RobustLoss(LossKind::kCauchy));
  EXPECT_LT((q - f.q_true).norm(), 1e-6) << q.transpose();
}

TEST(WholeTurns, NoTurnWithoutRoomForItAFrozenColumnOrAReading) {
  Frame f;
  // A frozen j2 stays where it is.
  const Eigen::VectorXd frozen =
      f.solvedFrom(kTurnOnJ2, RobustLoss(LossKind::kCauchy), {false, true, false});
  EXPECT_NEAR(frozen[1], f.q_true[1] + 2 * M_PI, 1e-9);
  // Without its pot's reading nothing says which turn: j2 stays.
  f.obs.joint(0, 1) = std::numeric_limits<double>::quiet_NaN();
  const Eigen::VectorXd missing = f.solvedFrom(kTurnOnJ2, RobustLoss(LossKind::kCauchy));
  EXPECT_NEAR(missing[1], f.q_true[1] + 2 * M_PI, 1e-6);
  // j1's limits (±1.5) hold no turn: it is no candidate at all.
  Eigen::VectorXd lower, upper;
  widenedLimits(f.robot, &lower, &upper);
  const std::vector<TurnSensor> sensors = turnSensors(f.model, lower, upper, {});
  ASSERT_EQ(sensors.size(), 2u);
  EXPECT_EQ(sensors[0].sensor, 1);
  EXPECT_EQ(sensors[1].sensor, 2);
}

TEST(WholeTurns, TurnsToFitOnlyOntoAMapThatExplainsTheReading) {
  TurnSensor s;
  const GainBias map{-2.0, 0.3};
  const double sigma = 0.01;  // a turn: 2π·2 = 1257 σ
  const double q = 1.1;
  const double reading = map.gain * q + map.bias;
  EXPECT_EQ(turnsToFit(s, map, sigma, reading, q), 0);
  EXPECT_EQ(turnsToFit(s, map, sigma, reading, q + 2 * M_PI), -1);
  EXPECT_EQ(turnsToFit(s, map, sigma, reading + 2.5 * sigma, q - 2 * M_PI), 1);
  EXPECT_EQ(turnsToFit(s, map, sigma, reading, q - 4 * M_PI), 2);
  // Beyond kMaxTurns: no turn.
  EXPECT_EQ(turnsToFit(s, map, sigma, reading, q - 3 * 2 * M_PI), 0);
  // A turn away the reading still misfits by 4 σ (or half a turn): the map
  // does not explain it, so no turn.
  EXPECT_EQ(turnsToFit(s, map, sigma, reading + 4 * sigma, q - 2 * M_PI), 0);
  EXPECT_EQ(turnsToFit(s, map, sigma, reading, q - 2 * M_PI + 0.5), 0);
  // A turn worth fewer than kTurnInSigma σ of reading: no turn.
  EXPECT_EQ(turnsToFit(s, map, 2 * 2 * M_PI / 90, reading, q + 2 * M_PI), 0);
  EXPECT_EQ(turnsToFit(s, map, 2 * 2 * M_PI / 110, reading, q + 2 * M_PI), -1);
  EXPECT_EQ(turnsToFit(s, map, sigma, std::numeric_limits<double>::quiet_NaN(), q), 0);
  // A mimic follower's angle: a turn of q moves it by multiplier turns.
  s.multiplier = -0.5;
  s.offset = 0.2;
  const double follower = -0.5 * q + 0.2;
  EXPECT_EQ(turnsToFit(s, map, sigma, map.gain * follower + map.bias, q - 2 * M_PI), 1);
}

}  // namespace
}  // namespace stac
