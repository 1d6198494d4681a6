// Joint angles held at a limit (verdict.hpp jointsOftenAtLimit): true
// angles never leave the URDF's limits, so a calibration that holds a
// joint's motion at the q-phase's bound in many frames is a wrong minimum
// or a URDF narrower than the robot. A chain whose j4 spans more than a
// turn (a UR arm's wrists): its pot's map a whole turn off puts most frames
// beyond a limit; a converged run finds the whole turn back
// (WideBasin::jumpToBetterMinimum, wholeTurnMoves), and limits narrower than
// the logged motion give verdict suspect with the joint named.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>

#include "methods/verdict.hpp"
#include "methods/wide_basin.hpp"
#include "solve/q_phase.hpp"
#include "stac/calibrate.hpp"
#include "stac/sensors_file.hpp"
#include "stac/simulate.hpp"

namespace stac {
namespace {

// j4's limits: [-4, 4] spans more than a turn; the motion logged is j4 over
// [-1, 2.5], which a whole turn up leaves entirely and a whole turn down
// mostly (only what lies above 1.88 rad stays within -4.4).
std::string chainUrdf(double j4_limit) {
  const std::string l = std::to_string(j4_limit);
  return R"(<robot name="chain4">
  <link name="base"/><link name="l1"/><link name="l2"/><link name="l3"/><link name="l4"/>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/>
    <origin xyz="0 0 0.1"/><axis xyz="0 0 1"/><limit lower="-1.5" upper="1.5" effort="1" velocity="1"/></joint>
  <joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/>
    <origin xyz="0 0 0.1"/><axis xyz="0 1 0"/><limit lower="-1.5" upper="1.5" effort="1" velocity="1"/></joint>
  <joint name="j3" type="revolute"><parent link="l2"/><child link="l3"/>
    <origin xyz="0.25 0 0"/><axis xyz="1 0 0"/><limit lower="-1.5" upper="1.5" effort="1" velocity="1"/></joint>
  <joint name="j4" type="revolute"><parent link="l3"/><child link="l4"/>
    <origin xyz="0.2 0 0"/><axis xyz="0 0 1"/><limit lower="-)" + l + R"(" upper=")" + l +
         R"(" effort="1" velocity="1"/></joint>
</robot>
)";
}

const char* kTruth = R"(mocap:
  sigma: 0.002
  frame:
    translation: [0.4, -0.2, 0.7]
    rpy: [0.2, -0.1, 1.0]
  markers:
    - {name: m_base, link: base, position: [0.05, 0.03, 0.0], fixed: true}
    - {name: m_l2, link: l2, position: [0.05, -0.04, 0.15]}
    - {name: m_l3, link: l3, position: [0.1, 0.05, 0.04]}
    - {name: m_l4a, link: l4, position: [0.04, 0.03, 0.05], fixed: true}
    - {name: m_l4b, link: l4, position: [0.06, -0.05, 0.02]}
joint_sensors:
  - {name: j1_pot, joint: j1, gain: -1.5, bias: 0.4, sigma: 0.01}
  - {name: j2_pot, joint: j2, gain: 2.1, bias: -0.7, sigma: 0.01}
  - {name: j3_pot, joint: j3, gain: 0.8, bias: 1.1, sigma: 0.01}
  - {name: j4_pot, joint: j4, gain: -1.2, bias: 0.2, sigma: 0.01}
)";

// The log simulated on the chain with j4 limits ±4; `urdf_j4_limit`: the
// limits of the URDF it is calibrated with.
struct Chain {
  explicit Chain(double urdf_j4_limit)
      : truth_robot(RobotModel::fromString(chainUrdf(4.0), "chain4")),
        robot(RobotModel::fromString(chainUrdf(urdf_j4_limit), "chain4")),
        truth(parseSensorsYaml(kTruth, "chain truth", robot)),
        model(truth_robot, truth.sensors) {
    std::mt19937_64 rng(5);
    q = simulateMotion(truth_robot, 400, 100.0, rng);
    const double lo = q.col(3).minCoeff(), hi = q.col(3).maxCoeff();
    q.col(3) = ((q.col(3).array() - lo) * (3.5 / (hi - lo)) - 1.0).matrix();
    SimulationOptions so;
    so.frames = 400;
    obs = bindLog(simulateLog(model, truth.theta, q, so, rng).log, truth.sensors, "chain", 1.0);
  }
  RobotModel truth_robot, robot;
  SensorsFile truth;
  MeasurementModel model;
  RowMatrix q;
  Observations obs;
};

TEST(JointLimits, JointsOftenAtALimitAreCountedFromThreeFramesAndAShare) {
  const Chain c(4.0);
  Eigen::VectorXd lower, upper;
  widenedLimits(c.robot, &lower, &upper);
  RowMatrix q = RowMatrix::Zero(100, 4);
  for (int t = 0; t < 5; ++t) q(t, 3) = upper[3];
  q(10, 1) = lower[1];
  q(11, 1) = lower[1] + 1e-3;  // near the bound is not at it
  EXPECT_EQ(atWidenedLimit(c.robot, q).count(), 6);
  EXPECT_EQ(jointsOftenAtLimit(c.robot, q, 0.02), std::vector<int>{3});
  EXPECT_TRUE(jointsOftenAtLimit(c.robot, q, 0.10).empty());
  q(12, 1) = q(13, 1) = lower[1];  // three frames of 100 on j2, above 2%
  EXPECT_EQ(jointsOftenAtLimit(c.robot, q, 0.02), (std::vector<int>{1, 3}));
}

TEST(JointLimits, AWholeTurnOnlyWhereTheLimitsSpanMoreThanOne) {
  const Chain c(4.0);
  const NoiseModel noise = NoiseModel::fromSeeds(c.truth.sensors);
  const RobustLoss loss;
  const MeasurementModel model(c.robot, c.truth.sensors);
  Workspaces ws = makeWorkspaces(model, 2);
  const WideBasin basin(model, c.obs, noise, loss, 2, &ws, c.truth.theta, false);
  const std::vector<MinimumMove> moves = wholeTurnMoves(c.robot, basin.guesses());
  ASSERT_EQ(moves.size(), 1u);
  ASSERT_EQ(moves[0].whole_turn.size(), 1u);
  const PotGuess& g = basin.guesses()[moves[0].whole_turn[0]];
  EXPECT_EQ(g.column, 3);
  // The pot's predictions stay; the angles move a whole turn toward the middle.
  SensorParameters theta = c.truth.theta;
  RowMatrix q = c.q;
  applyMove(c.robot, basin.guesses(), moves[0], &theta, &q);
  const GainBias& before = c.truth.theta.joint_sensor[g.sensor];
  const GainBias& after = theta.joint_sensor[g.sensor];
  for (int t = 0; t < q.rows(); ++t) {
    EXPECT_NEAR(q(t, 3), c.q(t, 3) - 2 * M_PI, 1e-12);
    EXPECT_NEAR(after.gain * q(t, 3) + after.bias, before.gain * c.q(t, 3) + before.bias, 1e-12);
  }
  std::vector<PotGuess> held = basin.guesses();
  for (PotGuess& h : held) h.bias_held = true;
  EXPECT_TRUE(wholeTurnMoves(c.robot, held).empty());
}

// Started a whole turn off on j4 (its pot's bias shifted by 2π·gain, its
// angles by -2π): the run converges there with most frames at j4's lower
// limit, finds the turn back, and ends at the truth with verdict ok.
TEST(JointLimits, AConvergedRunFindsAWholeTurnBack) {
  const Chain c(4.0);
  SensorParameters start = c.truth.theta;
  start.joint_sensor[3].bias += 2 * M_PI * start.joint_sensor[3].gain;
  RowMatrix q0 = c.q;
  q0.col(3).array() -= 2 * M_PI;
  CalibrationOptions o;
  o.threads = 2;
  const CalibrationResult r = calibrate(c.robot, c.truth.sensors, start, c.obs, o, nullptr, &q0);
  const GainBias& truth = c.truth.theta.joint_sensor[3];
  EXPECT_NEAR(r.theta.joint_sensor[3].bias, truth.bias, 4 * r.std.joint_sensor[3].bias);
  EXPECT_NEAR(r.theta.joint_sensor[3].gain, truth.gain, 4 * r.std.joint_sensor[3].gain);
  EXPECT_FALSE(r.summary.suspect()) << r.summary.verdict[0];
}

// A URDF whose j4 limits (±0.8) are narrower than the motion logged (j4
// over [-1, 2.5]): the calibration holds j4 at its limit in most frames and
// says so.
TEST(JointLimits, LimitsNarrowerThanTheMotionAreSuspect) {
  const Chain c(0.8);
  CalibrationOptions o;
  o.threads = 2;
  const CalibrationResult r =
      calibrate(c.robot, c.truth.sensors, c.truth.theta, c.obs, o, nullptr, &c.q);
  ASSERT_TRUE(r.summary.suspect());
  EXPECT_TRUE(std::any_of(r.summary.verdict.begin(), r.summary.verdict.end(),
                          [](const std::string& why) {
                            return why.find("joint j4 sits at its limit") == 0 &&
                                   why.find("of 400 frames") != std::string::npos;
                          }))
      << r.summary.verdict[0];
}

}  // namespace
}  // namespace stac
