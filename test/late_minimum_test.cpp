// Wrong minima found only late, or only from a placement: the silent misses
// of fresh basin truths (STAC_BASIN_TRUTH_SEED=11) on unseen robots with
// partial swings, replayed (test/fixtures), each must now reach the truth
// with verdict ok:
//  - Finger Edu, truth 4: a half-turn jump took the misfit away and left
//    the whole mirror image (mocap frame 3.05 rad off, every joint
//    mirrored), 0.2% worse than the truth's fit, which no round looked at
//    again (alternation.cpp jumpRounds: a round after every kept jump);
//  - Unitree Z1, truths 9 and 8 (and seed 7's truth 7): the roll above the
//    gripper 4.8 (1.6) rad off, the gripper's short swing mirrored and
//    rescaled, at the truth's cost; the roll's or the gripper's motion
//    beyond its limits in most frames (recentreMoves: placements over the
//    limits, the joint above placed with the one below mirrored); seed 13's
//    truth 0 (flagged) the gripper's motion wider than its limits.
// And the iteration limit's budget anew for a jump's run (goOnIfBetter).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "methods/wide_basin.hpp"
#include "solve/problem.hpp"
#include "solve/q_phase.hpp"
#include "stac/calibrate.hpp"
#include "support/basin_draws.hpp"
#include "support/chain_fixture.hpp"

namespace stac {
namespace {

test::Robot fixture(const std::string& name) {
  return test::externalRobot(
      RobotModel::fromFile(std::string(STAC_SOURCE_DIR) + "/test/fixtures/" + name), 600);
}

// The basin's partial-swing truth `index` of the draw `truth_seed`,
// calibrated with `options`.
CalibrationResult replay(const test::Robot& robot, int index, unsigned truth_seed,
                         SensorParameters* truth,
                         const CalibrationOptions& options = CalibrationOptions()) {
  auto [t, r] = test::replayBasinTruth(robot, test::Variant::kPartialSwings, index,
                                       LossKind::kHuber, options, 0, truth_seed);
  *truth = std::move(t);
  return std::move(r);
}

void expectReached(const test::Robot& robot, int index, unsigned truth_seed) {
  SensorParameters truth;
  const CalibrationResult r = replay(robot, index, truth_seed, &truth);
  std::string why;
  EXPECT_TRUE(test::closeToTruth(robot.truth.sensors, truth, r, &why)) << index << ": " << why;
  EXPECT_TRUE(r.summary.converged) << index;
  EXPECT_FALSE(r.summary.suspect()) << index << ": " << r.summary.verdict[0];
}

TEST(LateMinimum, AWholeMirrorLeftByAJumpIsFoundByTheNextRound) {
  expectReached(fixture("finger_edu_kinematics.urdf"), 4, 11);
}

TEST(LateMinimum, ARollAboveAShortGripperSwingIsPlacedBackInItsLimits) {
  const test::Robot z1 = fixture("z1_kinematics.urdf");
  expectReached(z1, 9, 11);  // the roll beyond its limits, the gripper mirrored
  expectReached(z1, 8, 11);  // only the gripper beyond them
  expectReached(z1, 7, 7);
  expectReached(z1, 0, 13);  // the gripper's motion 7.3 rad wide, its map 24x too flat
}

// Finger Edu truth 4 converges first after 13 iterations, jumps twice
// (after 13 and 22) and converges after 32. With a limit of 25 the second
// jump's run had 3 iterations left, not enough to fit better than where it
// jumped from, so the jump was dropped: the mirror image, verdict ok. As a
// descent of its own it has 25.
TEST(LateMinimum, AJumpsRunHasTheLimitsBudgetAnew) {
  const test::Robot robot = fixture("finger_edu_kinematics.urdf");
  CalibrationOptions o;
  o.max_iterations = 25;
  SensorParameters truth;
  const CalibrationResult r = replay(robot, 4, 11, &truth, o);
  EXPECT_TRUE(r.summary.converged);
  EXPECT_GT(r.summary.iterations, o.max_iterations);
  EXPECT_LT(r.summary.iterations, 2 * o.max_iterations);
  std::string why;
  EXPECT_TRUE(test::closeToTruth(robot.truth.sensors, truth, r, &why)) << why;
  EXPECT_FALSE(r.summary.suspect()) << r.summary.verdict[0];
}

// hand24 partial, fresh seed 13 truth 10: a jump's run crawls to its limit
// in another minimum of the middle finger (a marker's median error 1.76x
// its σ's, the truth's own fit 1.2x better in marker RMS), settled, its
// trade-off listed undetermined: verdict ok before; now suspect, as a crawl
// that converged only after many iterations still misfitting (and, first,
// for that marker, moved by pots whose gains are listed undetermined).
TEST(LateMinimum, ACrawlTheLimitStoppedStillMisfittingIsSuspect) {
  const test::Robot hand = test::bundledRobot("hand24", 500);
  SensorParameters truth;
  CalibrationOptions o;
  o.threads = 2;
  const CalibrationResult r = replay(hand, 10, 13, &truth, o);
  EXPECT_TRUE(r.summary.converged);
  EXPECT_GT(r.summary.iterations, o.max_iterations);
  ASSERT_GE(r.summary.verdict.size(), 2u);
  const std::string& crawl = r.summary.verdict.back();
  EXPECT_NE(crawl.find("converged only after"), std::string::npos) << crawl;
  EXPECT_NE(crawl.find("m_middle_"), std::string::npos) << crawl;
  EXPECT_NE(r.summary.verdict[0].find("m_middle_"), std::string::npos) << r.summary.verdict[0];
}

// The chain's j4 (±1.5) moved 2.5 rad up, beyond its limit in most frames.
struct J4Beyond : test::ChainLog {
  J4Beyond() : ChainLog(true, 5, {}) { q.col(3).array() += 2.5; }
};

double middle(const RowMatrix& q, int j) {
  return 0.5 * (q.col(j).maxCoeff() + q.col(j).minCoeff());
}

// Where recentre's `place` puts column j's middle: from the lowest middle
// that keeps the motion within the limits to the highest.
double placed(const RobotModel& robot, const RowMatrix& q, int j, double place) {
  const double half = 0.5 * (q.col(j).maxCoeff() - q.col(j).minCoeff());
  const double lo = robot.lowerLimits()[j] + half, hi = robot.upperLimits()[j] - half;
  return lo + place * (hi - lo);
}

// The chain's pot guesses, as the jumps make them.
std::vector<PotGuess> potGuessesOf(const test::ChainLog& c) {
  const NoiseModel noise = NoiseModel::fromSeeds(c.truth.sensors);
  const RobustLoss loss;
  Workspaces ws = makeWorkspaces(c.model, 2);
  const WideBasin basin(c.model, c.obs, noise, loss, 2, &ws, c.truth.theta, false);
  return basin.guesses();
}

TEST(Placements, AMotionBeyondItsLimitsIsPlacedOverThemAndTheJointAboveWithItMirrored) {
  const J4Beyond c;
  const std::vector<PotGuess> guesses = potGuessesOf(c);
  ASSERT_TRUE(beyondLimits(c.robot, c.q).col(3).count() > c.q.rows() / 2);
  const std::vector<MinimumMove> moves = recentreMoves(c.robot, guesses, c.q);
  ASSERT_EQ(moves.size(), 2u * kPlacements);  // j4 alone, then j3 with j4 mirrored
  const int g4 = moves[0].recentre.at(0);
  ASSERT_EQ(guesses[g4].column, 3);
  // Each pot's predictions stay; the moved motions lie within the limits.
  const auto predictions = [&](const SensorParameters& theta, const RowMatrix& q, int g) {
    const GainBias& m = theta.joint_sensor[guesses[g].sensor];
    return Eigen::VectorXd((m.gain * q.col(guesses[g].column)).array() + m.bias);
  };
  for (int k = 0; k < 2 * kPlacements; ++k) {
    const MinimumMove& move = moves[k];
    const double place = (k % kPlacements) / (kPlacements - 1.0);
    EXPECT_DOUBLE_EQ(move.place, place) << k;
    SensorParameters theta = c.truth.theta;
    RowMatrix q = c.q;
    applyMove(c.robot, guesses, move, &theta, &q);
    EXPECT_EQ(beyondLimits(c.robot, q).col(3).count(), 0) << k;
    const int g = move.recentre.at(0);
    EXPECT_LT((predictions(theta, q, g) - predictions(c.truth.theta, c.q, g)).cwiseAbs().maxCoeff(),
              1e-9) << k;
    EXPECT_LT((predictions(theta, q, g4) - predictions(c.truth.theta, c.q, g4)).cwiseAbs().maxCoeff(),
              1e-9) << k;
    EXPECT_NEAR(middle(q, guesses[g].column), placed(c.robot, c.q, guesses[g].column, place), 1e-9)
        << k;
    if (k < kPlacements) {
      EXPECT_TRUE(move.flip.empty());
      continue;
    }
    // j3 placed, j4 mirrored and in its limits' middle.
    EXPECT_EQ(guesses[g].column, 2);
    EXPECT_EQ(move.flip, std::vector<int>{g4});
    EXPECT_EQ(move.recentre_below, std::vector<int>{g4});
    EXPECT_NEAR(middle(q, 3), 0.0, 1e-9);
    EXPECT_NEAR(q(0, 3) - q(1, 3), -(c.q(0, 3) - c.q(1, 3)), 1e-9);
  }
  // A motion wider than the limits: shrunk to half their span, centred,
  // the pot's predictions kept (its map rescaled).
  RowMatrix wide = c.q;
  const double mid3 = middle(c.q, 3);
  wide.col(3) = (mid3 + 8 * (c.q.col(3).array() - mid3)).matrix();
  SensorParameters theta = c.truth.theta;
  GainBias& map = theta.joint_sensor[guesses[g4].sensor];
  map.bias += map.gain * mid3 * (1 - 1.0 / 8);
  map.gain /= 8;
  const SensorParameters wide_theta = theta;
  const std::vector<MinimumMove> shrink = recentreMoves(c.robot, guesses, wide);
  ASSERT_FALSE(shrink.empty());
  // One placement of it (every place would shrink it alike), then j3's.
  EXPECT_EQ(std::count_if(shrink.begin(), shrink.end(),
                          [&](const MinimumMove& m) { return m.recentre.at(0) == g4; }),
            1);
  RowMatrix q = wide;
  applyMove(c.robot, guesses, shrink[0], &theta, &q);
  const double span = c.robot.upperLimits()[3] - c.robot.lowerLimits()[3];
  EXPECT_NEAR(q.col(3).maxCoeff() - q.col(3).minCoeff(), 0.5 * span, 1e-9);
  EXPECT_NEAR(middle(q, 3), 0.0, 1e-9);
  EXPECT_LT((predictions(theta, q, g4) - predictions(wide_theta, wide, g4)).cwiseAbs().maxCoeff(),
            1e-9);
  // Within the limits, or with the bias held, no placement.
  RowMatrix inside = c.q;
  inside.col(3).array() -= 2.5;
  EXPECT_TRUE(recentreMoves(c.robot, guesses, inside).empty());
  std::vector<PotGuess> held = guesses;
  for (PotGuess& h : held) h.bias_held = true;
  EXPECT_TRUE(recentreMoves(c.robot, held, c.q).empty());
}

// A motion beyond the limits in fewer than most frames is placed only
// where its column is flagged (the verdict's criterion, which the jumps
// pass: WideBasin::jumpToBetterMinimum).
TEST(Placements, AMotionBeyondItsLimitsInAFewFramesIsPlacedWhereFlagged) {
  const J4Beyond c;
  const std::vector<PotGuess> guesses = potGuessesOf(c);
  // j4's motion shifted so that a fifth of its frames lie beyond its limit.
  RowMatrix q = c.q;
  Eigen::VectorXd sorted = q.col(3);
  std::sort(sorted.data(), sorted.data() + sorted.size());
  const double fifth = sorted[static_cast<Eigen::Index>(0.8 * (sorted.size() - 1))];
  q.col(3).array() += c.robot.upperLimits()[3] - fifth;
  const Eigen::Index beyond = beyondLimits(c.robot, q).col(3).count();
  ASSERT_GT(beyond, q.rows() / 10);
  ASSERT_LT(beyond, q.rows() / 2);
  EXPECT_TRUE(recentreMoves(c.robot, guesses, q).empty());
  const std::vector<MinimumMove> moves = recentreMoves(c.robot, guesses, q, {3});
  ASSERT_EQ(moves.size(), 2u * kPlacements);
  EXPECT_EQ(guesses[moves[0].recentre.at(0)].column, 3);
}

}  // namespace
}  // namespace stac
