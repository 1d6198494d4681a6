// The tree-order search of the pots' maps (src/methods/tree_search.hpp) and
// the biases known only modulo a turn (src/methods/turn_ambiguity.hpp), on
// ur5 (its joints' limits span two turns each) moved over 20-40% of each
// joint's range, off-centre: the wide basin's sweeps, which assume swings
// about each range's middle, end in mirror images there.
#include "methods/tree_search.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "methods/turn_ambiguity.hpp"
#include "stac/calibrate.hpp"
#include "stac/sensors_file.hpp"
#include "stac/simulate.hpp"
#include "support/arm_files.hpp"
#include "support/external_sensors.hpp"
#include "support/test_util.hpp"

namespace stac {
namespace {

RobotModel ur5() {
  return RobotModel::fromFile(std::string(STAC_SOURCE_DIR) + "/test/fixtures/ur5.urdf");
}

double wrap(double a) { return a - 2 * M_PI * std::round(a / (2 * M_PI)); }

struct Ur5Partial {
  explicit Ur5Partial(int seed) : robot(ur5()) {
    std::mt19937_64 rng(seed);
    file = parseSensorsYaml(test::inferableTruthYaml(robot, true, rng), "ur5 sensors", robot);
    const MeasurementModel model(robot, file.sensors);
    q = test::partialSwings(robot, simulateMotion(robot, 300, 100.0, rng), rng);
    SimulationOptions so;
    so.frames = 300;
    log = simulateLog(model, file.theta, q, so, rng).log;
  }
  // The paper's seeding: gains 1, biases 0, free markers at their link's
  // origin, the mocap frame identity.
  SensorParameters paperSeed() const {
    SensorParameters seed = file.theta;
    seed.mocap = MocapFrame();
    for (size_t m = 0; m < file.sensors.markers.size(); ++m)
      if (!file.sensors.markers[m].fixed) seed.marker_position[m].setZero();
    for (GainBias& gb : seed.joint_sensor) gb = {1.0, 0.0};
    return seed;
  }
  RobotModel robot;
  SensorsFile file;
  RowMatrix q;
  Log log;
};

TEST(TreeSearch, StartOffsetsCoverATurnOrTheRange) {
  const RobotModel robot = ur5();  // ±2π: one turn about the middle
  const std::vector<double> turn = startOffsets(robot, 0);
  ASSERT_EQ(turn.size(), 8u);
  EXPECT_NEAR(turn.back() - turn.front(), 7 * M_PI / 4, 1e-12);
  EXPECT_NEAR(turn.front() + turn.back(), 0.0, 1e-12);
  const RobotModel arm = RobotModel::fromString(test::kArmUrdf, "arm4");
  const std::vector<double> range = startOffsets(arm, 0);
  ASSERT_EQ(range.size(), 8u);
  const double lo = arm.lowerLimits()[0], hi = arm.upperLimits()[0];
  ASSERT_LT(hi - lo, 2 * M_PI);
  for (double m : range) EXPECT_TRUE(m > lo && m < hi) << m;
}

// The maps found invert the true pots (sign, scale, and offset modulo a
// turn), where the guessed maps (swings about the middle) are far off.
TEST(TreeSearch, FindsTheMapsOfOffCentrePartialSwings) {
  const Ur5Partial u(3);
  const MeasurementModel model(u.robot, u.file.sensors);
  const Observations obs = bindLog(u.log, u.file.sensors, "sim", 1.0);
  const Observations sub = selectFrames(obs, spreadFrames(obs.num_frames, 150));
  const SensorParameters seed = u.paperSeed();
  const std::vector<PotGuess> guesses =
      makePotGuesses(u.robot, u.file.sensors, seed, sub, false);
  ASSERT_EQ(static_cast<int>(guesses.size()), u.robot.dof());
  const auto found = treeOrderMaps(model, sub, RobustLoss(), guesses, seed, 2);
  ASSERT_TRUE(found.has_value());
  double worst_guess_offset = 0;
  for (size_t i = 0; i < guesses.size(); ++i) {
    const GainBias& gb = u.file.theta.joint_sensor[guesses[i].sensor];
    const double alpha = 1.0 / gb.gain, mid = (guesses[i].pivot - gb.bias) / gb.gain;
    EXPECT_NEAR(found->maps[i].alpha / alpha, 1.0, 0.1) << "joint " << i;
    EXPECT_NEAR(wrap(found->maps[i].mid - mid), 0.0, 0.1) << "joint " << i;
    worst_guess_offset = std::max(worst_guess_offset, std::abs(wrap(guesses[i].map.mid - mid)));
  }
  EXPECT_GT(worst_guess_offset, 0.5);  // the sweeps' start is far off
}

TEST(TreeSearch, NotForAJointWithoutAPotOfItsOwn) {
  const Ur5Partial u(3);
  SensorSet sensors = u.file.sensors;
  SensorParameters seed = u.paperSeed();
  sensors.ignore_columns.push_back(sensors.joint_sensors.back().name);
  sensors.joint_sensors.pop_back();  // the last joint has no pot
  seed.joint_sensor.pop_back();
  const MeasurementModel model(u.robot, sensors);
  const Observations obs = bindLog(u.log, sensors, "sim", 1.0);
  const std::vector<PotGuess> guesses = makePotGuesses(u.robot, sensors, seed, obs, false);
  EXPECT_FALSE(treeOrderMaps(model, obs, RobustLoss(), guesses, seed, 2).has_value());
}

// The search's two orders. Depth first: each joint is followed at once by
// every joint it moves (its limb below it), and comes after every joint
// that moves it; on a hand, breadth first (every finger's base, then every
// middle joint, ...) is another order.
TEST(TreeSearch, OrdersAreDepthAndBreadthFirst) {
  const RobotModel hand = RobotModel::fromFile(test::dataPath("hand24.urdf"));
  const std::vector<int> order = treeOrder(hand, true);
  ASSERT_EQ(static_cast<int>(order.size()), hand.dof());
  auto moves = [&](int a, int c) {  // whether column a moves column c
    const auto& path =
        hand.supportingJoints(hand.movableJoints()[hand.qJoints()[c]].child_link);
    return std::find(path.begin(), path.end(), hand.qJoints()[a]) != path.end();
  };
  int branching = 0;
  for (int k = 0; k < hand.dof(); ++k) {
    const int a = order[k];
    int below = 0;
    for (int c = 0; c < hand.dof(); ++c) below += c != a && moves(a, c);
    for (int i = 0; i < hand.dof(); ++i) {
      const int c = order[i];
      if (c == a) continue;
      if (i < k) {
        EXPECT_FALSE(moves(a, c)) << hand.qName(a) << " before " << hand.qName(c);
      }
      if (i > k) {
        EXPECT_FALSE(moves(c, a)) << hand.qName(c) << " after " << hand.qName(a);
      }
      if (i > k && i <= k + below) {
        EXPECT_TRUE(moves(a, c)) << hand.qName(a) << "'s limb broken by " << hand.qName(c);
      }
    }
    int children = 0;
    for (int c = 0; c < hand.dof(); ++c)
      if (c != a && moves(a, c)) {
        bool direct = true;
        for (int m = 0; m < hand.dof(); ++m)
          if (m != a && m != c && moves(a, m) && moves(m, c)) direct = false;
        children += direct;
      }
    branching += children > 1;
  }
  EXPECT_GT(branching, 0);  // the hand branches: breadth first differs
  // Breadth first: by the number of joints above, every joint after those
  // that move it.
  const std::vector<int> breadth = treeOrder(hand, false);
  ASSERT_EQ(breadth.size(), order.size());
  EXPECT_NE(breadth, order);
  auto depth = [&](int c) {
    return hand.supportingJoints(hand.movableJoints()[hand.qJoints()[c]].child_link).size();
  };
  for (int k = 1; k < hand.dof(); ++k) EXPECT_LE(depth(breadth[k - 1]), depth(breadth[k]));
}

// ---- Turns ----

TEST(TurnAmbiguity, ListedWhenTheMotionFitsATurnAway) {
  const Ur5Partial u(3);
  const MeasurementModel model(u.robot, u.file.sensors);
  RowMatrix q = RowMatrix::Zero(2, u.robot.dof());
  q.row(0).setConstant(0.5);
  q.row(1).setConstant(1.5);  // [0.5, 1.5] fits one turn lower too
  q(0, 0) = -6.0;  // joint 0: [-6, 1.5] fits in ±2π (widened 5%) only where it is
  const std::vector<UnidentifiableDirection> listed = turnAmbiguities(model, u.file.theta, q);
  // A motion 1 rad wide fits a turn away where the widened limits span a
  // turn and a radian (ur5's elbow spans one turn only).
  std::vector<std::string> expected;
  for (int j = 1; j < u.robot.dof(); ++j)
    if (1.1 * (u.robot.upperLimits()[j] - u.robot.lowerLimits()[j]) >= 2 * M_PI + 1.0)
      expected.push_back("joint_sensors." + u.file.sensors.joint_sensors[j].name + ".bias");
  ASSERT_GE(expected.size(), 3u);
  ASSERT_EQ(listed.size(), expected.size());
  for (size_t k = 0; k < listed.size(); ++k) {
    EXPECT_EQ(listed[k].parameters[0], expected[k]);
    EXPECT_NE(listed[k].reason.find("modulo a turn"), std::string::npos);
    EXPECT_EQ(listed[k].kind, Undetermined::kModuloTurn);
  }
  EXPECT_NE(listed[0].reason.find(u.robot.qName(1)), std::string::npos);
}

TEST(TurnAmbiguity, NotForAHeldBiasOrLimitsWithinATurn) {
  Ur5Partial u(3);
  u.file.sensors.joint_sensors[2].fixed.bias = true;
  const MeasurementModel model(u.robot, u.file.sensors);
  RowMatrix q = RowMatrix::Zero(1, u.robot.dof());
  for (const UnidentifiableDirection& d : turnAmbiguities(model, u.file.theta, q))
    EXPECT_NE(d.parameters[0], "joint_sensors." + u.file.sensors.joint_sensors[2].name + ".bias");
  const RobotModel arm = RobotModel::fromString(test::kArmUrdf, "arm4");
  const SensorsFile f = parseSensorsYaml(test::kArmTruth, "arm4", arm);
  const MeasurementModel arm_model(arm, f.sensors);
  EXPECT_TRUE(turnAmbiguities(arm_model, f.theta, RowMatrix::Zero(3, arm.dof())).empty());
  // A motion a whole turn above arm4's limits (±1.5) "fits a turn lower",
  // but it is no placement of the joint: a wrong minimum, not an ambiguity.
  EXPECT_TRUE(
      turnAmbiguities(arm_model, f.theta, RowMatrix::Constant(3, arm.dof(), 2 * M_PI + 0.5))
          .empty());
}

RobotModel arm4ContinuousBase() {
  return RobotModel::fromString(test::armUrdfWithContinuousBase(), "arm4_continuous_base");
}

// A continuous joint's pots are written with the bias nearest zero (within
// half a turn), the joint's angles moved by the same turns; a revolute
// joint and a held bias are left as they are.
TEST(TurnAmbiguity, AContinuousJointsBiasIsWrittenWithinHalfATurnOfZero) {
  const RobotModel robot = arm4ContinuousBase();
  SensorsFile f = parseSensorsYaml(test::kArmTruth, "arm4_truth", robot);
  auto twoTurnsOff = [&](SensorParameters* theta, RowMatrix* q) {
    *theta = f.theta;
    *q = RowMatrix::Constant(3, robot.dof(), 0.2);
    for (int s : {0, 1}) {  // p = g·q + b = g·(q − 4π) + (b + 4π·g)
      theta->joint_sensor[s].bias += 4 * M_PI * theta->joint_sensor[s].gain;
      q->col(s).array() -= 4 * M_PI;
    }
  };
  SensorParameters theta;
  RowMatrix q;
  twoTurnsOff(&theta, &q);
  const MeasurementModel model(robot, f.sensors);
  nearestTurnForContinuousJoints(model, &theta, &q);
  EXPECT_NEAR(theta.joint_sensor[0].bias, f.theta.joint_sensor[0].bias, 1e-12);
  EXPECT_NEAR(q(2, 0), 0.2, 1e-12);
  EXPECT_NEAR(theta.joint_sensor[1].bias, f.theta.joint_sensor[1].bias + 4 * M_PI * 2.1, 1e-12);
  EXPECT_NEAR(q(2, 1), 0.2 - 4 * M_PI, 1e-12);  // j2 is revolute
  f.sensors.joint_sensors[0].fixed.bias = true;
  const MeasurementModel held(robot, f.sensors);
  twoTurnsOff(&theta, &q);
  nearestTurnForContinuousJoints(held, &theta, &q);
  EXPECT_NEAR(q(2, 0), 0.2 - 4 * M_PI, 1e-12);
}

// Whole turns until the fewest frames lie beyond the joint's limits: a
// motion partly beyond ur5's -2π comes back a turn up (or two, from
// further), one a turn above arm4's 1.5 a turn down; a motion inside stays
// (a turn up fits as well), and so does one that no turn brings further
// inside. Not where something else sees the turns: a held bias, a
// continuous joint (no limits).
TEST(TurnAmbiguity, AMotionBeyondItsLimitsIsTurnedBackInside) {
  const RobotModel robot = ur5();
  std::mt19937_64 rng(3);
  SensorsFile f =
      parseSensorsYaml(test::inferableTruthYaml(robot, true, rng), "ur5 sensors", robot);
  const MeasurementModel model(robot, f.sensors);
  using Eigen::VectorXd;
  VectorXd below = VectorXd::LinSpaced(50, -8.5, -1.0);
  EXPECT_EQ(turnsIntoLimits(model, 0, below), 1);
  EXPECT_EQ(turnsIntoLimits(model, 0, -below), -1);
  EXPECT_EQ(turnsIntoLimits(model, 0, VectorXd::LinSpaced(50, -16.0, -9.0)), 2);
  EXPECT_EQ(turnsIntoLimits(model, 0, VectorXd::LinSpaced(50, -1.0, 0.0)), 0);
  EXPECT_EQ(turnsIntoLimits(model, 0, VectorXd::LinSpaced(50, -7.0, 7.0)), 0);
  below.head(40).setConstant(std::numeric_limits<double>::quiet_NaN());  // no readings
  below.tail(10).setConstant(-1.0);
  EXPECT_EQ(turnsIntoLimits(model, 0, below), 0);
  for (JointSensorConfig& js : f.sensors.joint_sensors)
    if (robot.movableJoints()[js.joint].q_index == 0) js.fixed.bias = true;
  const MeasurementModel held(robot, f.sensors);
  EXPECT_EQ(turnsIntoLimits(held, 0, VectorXd::LinSpaced(50, -8.5, -1.0)), 0);

  const RobotModel arm = RobotModel::fromString(test::kArmUrdf, "arm4");
  const SensorsFile a = parseSensorsYaml(test::kArmTruth, "arm4", arm);
  const MeasurementModel arm_model(arm, a.sensors);
  const VectorXd above = VectorXd::LinSpaced(20, 2 * M_PI - 1.0, 2 * M_PI + 1.0);
  EXPECT_EQ(turnsIntoLimits(arm_model, 0, above), -1);
  const RobotModel continuous = arm4ContinuousBase();
  const SensorsFile c = parseSensorsYaml(test::kArmTruth, "arm4_truth", continuous);
  EXPECT_EQ(turnsIntoLimits(MeasurementModel(continuous, c.sensors), 0, above), 0);
}

// Through the whole calibration: started a turn off on the continuous
// joint (the same fit), the result is written nearest zero, where the
// truth's bias is, within its std. Before, it stayed a turn off with a
// sharp std: a confident wrong number to anyone comparing biases.
TEST(TurnAmbiguity, ACalibrationAWholeTurnOffIsWrittenNearestZero) {
  const RobotModel robot = arm4ContinuousBase();
  const SensorsFile f = parseSensorsYaml(test::kArmTruth, "arm4_truth", robot);
  const MeasurementModel model(robot, f.sensors);
  std::mt19937_64 rng(11);
  RowMatrix q = simulateMotion(robot, 300, 100.0, rng);
  SimulationOptions so;
  so.frames = 300;
  const Observations obs =
      bindLog(simulateLog(model, f.theta, q, so, rng).log, f.sensors, "arm4", 1.0);
  SensorParameters start = f.theta;
  start.joint_sensor[0].bias += 2 * M_PI * start.joint_sensor[0].gain;
  q.col(0).array() -= 2 * M_PI;
  CalibrationOptions o;
  o.threads = 2;
  const CalibrationResult r = calibrate(robot, f.sensors, start, obs, o, nullptr, &q);
  EXPECT_FALSE(r.summary.suspect()) << r.summary.verdict[0];
  EXPECT_NEAR(r.theta.joint_sensor[0].bias, f.theta.joint_sensor[0].bias,
              4 * r.std.joint_sensor[0].bias);
  EXPECT_TRUE(std::isfinite(r.std.joint_sensor[0].bias));
}

// The whole calibration from the paper's seeding reaches the truth, up to
// the turns it reports.
TEST(TreeSearch, CalibrationOfPartialSwingsReachesTheTruthModuloReportedTurns) {
  const Ur5Partial u(5);
  const Observations obs = bindLog(u.log, u.file.sensors, "sim", 1.0);
  CalibrationOptions o;
  o.threads = 2;
  const CalibrationResult r = calibrate(u.robot, u.file.sensors, u.paperSeed(), obs, o);
  EXPECT_FALSE(r.summary.suspect()) << r.summary.verdict[0];
  for (size_t s = 0; s < u.file.sensors.joint_sensors.size(); ++s) {
    const GainBias& truth = u.file.theta.joint_sensor[s];
    const GainBias& got = r.theta.joint_sensor[s];
    EXPECT_NEAR(got.gain, truth.gain, 5 * r.std.joint_sensor[s].gain + 1e-3) << s;
    bool modulo_turn = false;
    for (const UnidentifiableDirection& d : r.summary.unidentifiable)
      modulo_turn |= d.parameters[0] == "joint_sensors." + u.file.sensors.joint_sensors[s].name +
                                            ".bias";
    double e = got.bias - truth.bias;
    const double turn = 2 * M_PI * std::abs(truth.gain);
    if (!modulo_turn) {
      EXPECT_NEAR(e, 0.0, 5 * r.std.joint_sensor[s].bias + 1e-3) << s;
      continue;
    }
    // Listed: no std (it is known only modulo a turn), and right modulo it
    // to a tenth of a radian or two (the last joint's bias, which trades
    // against the markers on its link, was 0.09 off with a local std of
    // 0.02 or more; a wrong minimum is radians off).
    EXPECT_TRUE(std::isinf(r.std.joint_sensor[s].bias)) << s;
    EXPECT_NEAR(e - turn * std::round(e / turn), 0.0, 0.2) << s;
  }
}

}  // namespace
}  // namespace stac
