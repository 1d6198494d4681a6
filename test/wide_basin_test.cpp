// The wide-basin initialisation's parts (src/methods/wide_basin.hpp), each on
// a small problem whose truth is known: the 4-joint arm of arm_fixture (a
// pot on every joint, gains of either sign) and the bundled gimbal2.
#include "methods/wide_basin.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "stac/kinematics.hpp"
#include "stac/calibrate.hpp"
#include "stac/sensors_file.hpp"
#include "stac/simulate.hpp"
#include "support/arm_files.hpp"
#include "support/arm_fixture.hpp"
#include "support/test_util.hpp"

namespace stac {
namespace {

constexpr int kThreads = 2;

// Everything a WideBasin refers to, for one problem.
struct ArmSetup {
  explicit ArmSetup(test::ArmProblem problem)
      : p(std::move(problem)), model(p.robot, p.sensors), noise(NoiseModel::fromSeeds(p.sensors)) {
    for (int i = 0; i < kThreads; ++i) ws.emplace_back(model);
  }
  WideBasin basin(const SensorParameters& seed) {
    return WideBasin(model, p.obs, noise, loss, kThreads, &ws, seed, true);
  }
  test::ArmProblem p;
  MeasurementModel model;
  NoiseModel noise;
  RobustLoss loss;
  std::vector<FrameWorkspace> ws;
};

// The arm of arm_fixture (seed 11). Its mocap rotation's axis comes from
// Eigen's Random(), i.e. std::rand(): seeded here so that the truth does not
// depend on which tests ran before.
test::ArmProblem arm(int frames) {
  std::srand(1);
  return test::makeArmProblem(frames, 11);
}

// The maps that invert the true pots: q = (p - b) / g = alpha (p - pivot) + mid.
Candidate truthMaps(const std::vector<PotGuess>& guesses, const SensorParameters& truth) {
  Candidate c;
  for (const PotGuess& g : guesses) {
    const GainBias& gb = truth.joint_sensor[g.sensor];
    c.maps.push_back({1.0 / gb.gain, (g.pivot - gb.bias) / gb.gain});
  }
  return c;
}

// The truth's θ and angles.
Estimate atTheTruth(const test::ArmProblem& p) {
  Estimate est;
  est.theta = p.truth;
  est.state.q = p.q_true;
  return est;
}

// The largest of the joints' RMS errors (pot noise alone gives up to
// 0.01 / 0.5 = 0.02 rad on the arm).
double worstRmsError(const RowMatrix& q, const RowMatrix& truth) {
  return (q - truth).colwise().norm().maxCoeff() / std::sqrt(static_cast<double>(q.rows()));
}

void expectSignsOf(const Candidate& c, const std::vector<PotGuess>& guesses,
                   const SensorParameters& truth) {
  for (size_t i = 0; i < guesses.size(); ++i)
    EXPECT_EQ(c.maps[i].alpha > 0, truth.joint_sensor[guesses[i].sensor].gain > 0) << "guess " << i;
}

// Arm readings without noise along a motion that spans exactly 80% of every
// joint's range, symmetric about its middle (whole periods of a cosine).
test::ArmProblem eightyPercentArm() {
  test::ArmProblem p = arm(10);
  const int frames = 200;
  p.q_true.resize(frames, p.robot.dof());
  for (int j = 0; j < p.robot.dof(); ++j) {
    const double lo = p.robot.lowerLimits()[j], hi = p.robot.upperLimits()[j];
    for (int t = 0; t < frames; ++t)
      p.q_true(t, j) = 0.5 * (lo + hi) + 0.4 * (hi - lo) * std::cos(2 * M_PI * t / frames);
  }
  const MeasurementModel model(p.robot, p.sensors);
  std::mt19937 rng(1);
  test::simulateReadings(model, p.truth, p.q_true, 0.0, 0.0, rng, &p.obs);
  return p;
}

// ---- Pot guesses and candidates ----

TEST(PotGuesses, MapReadingsOntoTheJointRangeUpToSign) {
  const test::ArmProblem p = eightyPercentArm();
  const std::vector<PotGuess> guesses =
      makePotGuesses(p.robot, p.sensors, p.seed, p.obs);
  ASSERT_EQ(guesses.size(), 4u);
  RowMatrix q = RowMatrix::Zero(p.obs.num_frames, p.robot.dof());
  applyCandidate(guesses, guessedMaps(guesses), p.obs, &q);
  std::vector<bool> wrong(guesses.size());
  for (size_t i = 0; i < guesses.size(); ++i) {
    const PotGuess& g = guesses[i];
    const double gain = p.truth.joint_sensor[g.sensor].gain;
    EXPECT_EQ(g.column, static_cast<int>(i));
    EXPECT_NEAR(std::abs(g.map.alpha), 1.0 / std::abs(gain), 1e-9);
    EXPECT_GT(g.map.alpha, 0);  // the sign is the markers' to choose
    // The right time course, mirrored about the middle where the gain is
    // negative.
    const double mid = g.map.mid;
    for (int t = 0; t < p.obs.num_frames; ++t)
      EXPECT_NEAR(q(t, g.column),
                  gain > 0 ? p.q_true(t, g.column) : 2 * mid - p.q_true(t, g.column), 1e-9);
    wrong[i] = gain < 0;
  }
  applyCandidate(guesses, withSigns(guessedMaps(guesses), guesses, wrong), p.obs, &q);
  EXPECT_LT((q - p.q_true).cwiseAbs().maxCoeff(), 1e-9);
}

// Under a robust loss the span comes from the 5-95% quantiles: 5% gross
// readings (20-60 σ) no longer set the map's scale, while the clean guess
// is the min/max one (within the quantiles' share of an 80% swing).
TEST(PotGuesses, GrossReadingsDoNotSetTheScaleUnderARobustLoss) {
  const test::ArmProblem clean = eightyPercentArm();
  test::ArmProblem p = clean;
  test::addOutliers(p.sensors, 0.05, 7, &p.obs);
  const std::vector<PotGuess> exact = makePotGuesses(clean.robot, clean.sensors, clean.seed,
                                                     clean.obs);
  const std::vector<PotGuess> naive = makePotGuesses(p.robot, p.sensors, p.seed, p.obs);
  const std::vector<PotGuess> robust = makePotGuesses(p.robot, p.sensors, p.seed, p.obs, true);
  ASSERT_EQ(robust.size(), exact.size());
  double naive_worst = 0, robust_worst = 0;
  for (size_t i = 0; i < exact.size(); ++i) {
    naive_worst = std::max(naive_worst, std::abs(naive[i].map.alpha / exact[i].map.alpha - 1));
    robust_worst = std::max(robust_worst, std::abs(robust[i].map.alpha / exact[i].map.alpha - 1));
    EXPECT_EQ(robust[i].map.mid, exact[i].map.mid);
  }
  EXPECT_GT(naive_worst, 0.15);  // min/max: the outliers' span (20% here)
  EXPECT_LT(robust_worst, 0.05);  // quantiles: the motion's (1.5% here)
}

TEST(PotGuesses, FixedSensorIsInvertedExactlyAndNeverChanged) {
  test::ArmProblem p = eightyPercentArm();
  p.sensors.joint_sensors[2].fixed = FixedGainBias::both(true);
  p.seed.joint_sensor[2] = p.truth.joint_sensor[2];
  const std::vector<PotGuess> guesses = makePotGuesses(p.robot, p.sensors, p.seed, p.obs);
  ASSERT_EQ(guesses.size(), 4u);
  ASSERT_TRUE(guesses[2].fixed);
  const Candidate c = guessedMaps(guesses);
  const PotMap exact = truthMaps(guesses, p.truth).maps[2];
  EXPECT_NEAR(c.maps[2].alpha, exact.alpha, 1e-12);
  EXPECT_NEAR(c.maps[2].mid, exact.mid, 1e-12);
  const Candidate changed = scaled(withSigns(c, guesses, {true, true, true, true}), guesses, 0.5);
  EXPECT_EQ(changed.maps[2].alpha, c.maps[2].alpha);
  EXPECT_EQ(changed.maps[0].alpha, -0.5 * c.maps[0].alpha);
  EXPECT_TRUE(touchesFixed(guesses, {1, 2}));
  EXPECT_FALSE(touchesFixed(guesses, {0, 1}));
}

TEST(PotGuesses, MissingReadingsHoldTheLastAngle) {
  test::ArmProblem p = eightyPercentArm();
  p.obs.joint(0, 1) = NAN;
  p.obs.joint(5, 1) = NAN;
  const std::vector<PotGuess> guesses = makePotGuesses(p.robot, p.sensors, p.seed, p.obs);
  const Candidate c = truthMaps(guesses, p.truth);
  RowMatrix q = RowMatrix::Zero(p.obs.num_frames, p.robot.dof());
  applyCandidate(guesses, c, p.obs, &q);
  EXPECT_EQ(q(0, 1), c.maps[1].mid);
  EXPECT_NEAR(q(4, 1), p.q_true(4, 1), 1e-9);
  EXPECT_EQ(q(5, 1), q(4, 1));
  EXPECT_NEAR(q(6, 1), p.q_true(6, 1), 1e-9);
}

TEST(Candidates, TransformsAreValues) {
  const test::ArmProblem p = eightyPercentArm();
  const std::vector<PotGuess> guesses = makePotGuesses(p.robot, p.sensors, p.seed, p.obs);
  const Candidate c = guessedMaps(guesses);
  const Candidate f = flipped(c, {1, 3});
  const Candidate r = rescaled(c, 2, 4.0);
  for (size_t i = 0; i < guesses.size(); ++i) {
    EXPECT_EQ(f.maps[i].alpha, (i == 1 || i == 3 ? -1 : 1) * c.maps[i].alpha);
    EXPECT_EQ(r.maps[i].alpha, (i == 2 ? 4 : 1) * c.maps[i].alpha);
    EXPECT_EQ(f.maps[i].mid, c.maps[i].mid);
  }
  // The seed's maps inverted where it has a usable gain.
  SensorParameters seed = p.truth;
  seed.joint_sensor[1].gain = 0;
  const Candidate s = seededMaps(c, guesses, seed);
  const Candidate truth = truthMaps(guesses, p.truth);
  EXPECT_NEAR(s.maps[0].alpha, truth.maps[0].alpha, 1e-12);
  EXPECT_NEAR(s.maps[0].mid, truth.maps[0].mid, 1e-12);
  EXPECT_EQ(s.maps[1].alpha, c.maps[1].alpha);
}

TEST(Candidates, MirrorPatternsFollowTheJointAxes) {
  // The arm's axes at the neutral pose: z, y, x, z.
  const test::ArmProblem p = arm(10);
  const std::vector<PotGuess> guesses = makePotGuesses(p.robot, p.sensors, p.seed, p.obs);
  const std::vector<std::vector<bool>> patterns = mirrorPatterns(p.robot, guesses);
  ASSERT_EQ(patterns.size(), 4u);
  EXPECT_EQ(patterns[0], std::vector<bool>({true, true, true, true}));
  EXPECT_EQ(patterns[1], std::vector<bool>({true, true, false, true}));   // about x
  EXPECT_EQ(patterns[2], std::vector<bool>({true, false, true, true}));   // about y
  EXPECT_EQ(patterns[3], std::vector<bool>({false, true, true, false}));  // about z
}

TEST(Candidates, SignMovesAreSinglesThenPairsWithTheJointAbove) {
  const test::ArmProblem p = arm(10);
  const std::vector<PotGuess> guesses = makePotGuesses(p.robot, p.sensors, p.seed, p.obs);
  const std::vector<std::vector<int>> expected = {{0}, {1}, {2}, {3}, {0, 1}, {1, 2}, {2, 3}};
  EXPECT_EQ(signMoves(p.robot, guesses), expected);
}

TEST(Candidates, FlipSignKeepsThePotsPredictionsAndMirrorsTheJoint) {
  const test::ArmProblem p = arm(50);
  const MeasurementModel model(p.robot, p.sensors);
  const std::vector<PotGuess> guesses = makePotGuesses(p.robot, p.sensors, p.seed, p.obs);
  SensorParameters theta = p.truth;
  RowMatrix q = p.q_true;
  flipSign(guesses[1], &theta, &q);
  EXPECT_EQ(theta.joint_sensor[1].gain, -p.truth.joint_sensor[1].gain);
  const double c = p.q_true.col(1).mean();
  KinematicsWorkspace kin(p.robot);
  std::vector<double> pm(15), before(4), after(4), pt(1);
  for (int t = 0; t < 50; ++t) {
    EXPECT_NEAR(q(t, 1), 2 * c - p.q_true(t, 1), 1e-12);
    predictFrame(model, p.truth, p.q_true.row(t).transpose(), &kin, pm.data(), before.data(),
                 pt.data());
    predictFrame(model, theta, q.row(t).transpose(), &kin, pm.data(), after.data(), pt.data());
    for (int j = 0; j < 4; ++j) EXPECT_NEAR(after[j], before[j], 1e-12);
  }
}

TEST(Candidates, MisfitSeenOnlyWhenASignIsWrong) {
  const test::ArmProblem p = arm(150);
  const MeasurementModel model(p.robot, p.sensors);
  const NoiseModel noise = NoiseModel::fromSeeds(p.sensors);
  EXPECT_FALSE(someSensorMisfits(model, p.truth, noise, p.obs, p.q_true));
  const std::vector<PotGuess> guesses = makePotGuesses(p.robot, p.sensors, p.seed, p.obs);
  SensorParameters theta = p.truth;
  RowMatrix q = p.q_true;
  flipSign(guesses[3], &theta, &q);  // the pots still fit, the markers not
  EXPECT_TRUE(someSensorMisfits(model, theta, noise, p.obs, q));
}

// ---- The candidate search ----

TEST(WideBasinSearch, ScorePrefersTheTrueSigns) {
  ArmSetup s(arm(300));
  const WideBasin wb = s.basin(s.p.seed);
  const std::vector<PotGuess>& guesses = wb.guesses();
  const Candidate truth = truthMaps(guesses, s.p.truth);
  const SearchState at_truth = wb.startSearch(truth);
  // The mocap frame and markers re-solved from the seed fit the markers as
  // well as their true values do at the same q (the pots' inverse).
  QState q_of_pots;
  q_of_pots.q = neutralPose(s.p.robot).transpose().replicate(wb.subsample().num_frames, 1);
  applyCandidate(guesses, truth, wb.subsample(), &q_of_pots.q);
  FrameOptions markers;
  markers.group_weight[1] = markers.group_weight[2] = 0.0;
  const double truth_cost = totalCost(s.model, s.p.truth, s.noise, s.loss, wb.subsample(), markers,
                                      kThreads, &s.ws, &q_of_pots);
  EXPECT_LT(at_truth.cost, 1.01 * truth_cost);
  for (int i = 0; i < 4; ++i)
    EXPECT_GT(wb.score(flipped(truth, {i}), at_truth).cost, 2 * at_truth.cost) << "guess " << i;
  for (const std::vector<bool>& pattern : mirrorPatterns(s.p.robot, guesses))
    EXPECT_GT(wb.score(withSigns(truth, guesses, pattern), at_truth).cost, 2 * at_truth.cost);
  // The score does not depend on the search's damping or on a previous score.
  EXPECT_EQ(wb.score(truth, at_truth).cost, wb.score(truth, at_truth).cost);
}

TEST(WideBasinSearch, OfferKeepsOnlyABetterCandidate) {
  ArmSetup s(arm(300));
  const WideBasin wb = s.basin(s.p.seed);
  const Candidate truth = truthMaps(wb.guesses(), s.p.truth);
  SearchState st = wb.startSearch(flipped(truth, {2}));
  const double wrong_cost = st.cost;
  EXPECT_FALSE(wb.offer(flipped(truth, {1, 2}), 1.0, &st));
  EXPECT_EQ(st.cost, wrong_cost);
  EXPECT_TRUE(wb.offer(truth, 1.0, &st));
  EXPECT_LT(st.cost, wrong_cost);
  expectSignsOf(st.best, wb.guesses(), s.p.truth);
}

TEST(WideBasinSearch, SignSweepsRightWrongSigns) {
  ArmSetup s(arm(300));
  const WideBasin wb = s.basin(s.p.seed);
  const Candidate truth = truthMaps(wb.guesses(), s.p.truth);
  for (const std::vector<int>& wrong : std::vector<std::vector<int>>{{0}, {3}, {1, 2}, {0, 2}}) {
    SearchState st = wb.startSearch(flipped(truth, wrong));
    EXPECT_TRUE(wb.signSweeps(&st));
    expectSignsOf(st.best, wb.guesses(), s.p.truth);
  }
}

TEST(WideBasinSearch, RescaleSweepFindsEachJointsScale) {
  ArmSetup s(arm(300));
  const WideBasin wb = s.basin(s.p.seed);
  const Candidate truth = truthMaps(wb.guesses(), s.p.truth);
  SearchState st = wb.startSearch(rescaled(rescaled(truth, 2, 4.0), 0, 0.5));
  EXPECT_TRUE(wb.rescaleSweep(&st));
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(st.best.maps[i].alpha, truth.maps[i].alpha, 1e-12);
}

TEST(WideBasinSearch, MirrorSweepFindsAllSignsNegative) {
  test::ArmProblem p = arm(300);
  for (GainBias& gb : p.truth.joint_sensor) gb.gain = -std::abs(gb.gain);
  std::mt19937 rng(5);
  test::simulateReadings(MeasurementModel(p.robot, p.sensors), p.truth, p.q_true, 1.0, 0.0, rng,
                         &p.obs);
  ArmSetup s(std::move(p));
  const WideBasin wb = s.basin(s.p.seed);
  SearchState st = wb.startSearch(guessedMaps(wb.guesses()));
  wb.mirrorSweep(&st);
  expectSignsOf(st.best, wb.guesses(), s.p.truth);
}

TEST(WideBasinSearch, SeedsOwnMapsWinWhenRight) {
  ArmSetup s(arm(300));
  const WideBasin wb = s.basin(s.p.truth);
  SearchState st = wb.startSearch(guessedMaps(wb.guesses()));
  wb.seedCheck(&st);
  const Candidate truth = truthMaps(wb.guesses(), s.p.truth);
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(st.best.maps[i].alpha, truth.maps[i].alpha, 1e-12);
}

TEST(WideBasinSearch, SearchFindsTheSignsAndRoughScales) {
  ArmSetup s(arm(400));
  const WideBasin wb = s.basin(s.p.seed);
  const Candidate found = wb.searchPotMaps();
  expectSignsOf(found, wb.guesses(), s.p.truth);
  const Candidate truth = truthMaps(wb.guesses(), s.p.truth);
  // Scales are powers of two times the 80%-coverage guess, and a sweep
  // stops at the first that fits not clearly better: within a factor 2.5.
  for (int i = 0; i < 4; ++i) {
    EXPECT_GT(found.maps[i].alpha / truth.maps[i].alpha, 0.4) << "guess " << i;
    EXPECT_LT(found.maps[i].alpha / truth.maps[i].alpha, 2.5) << "guess " << i;
  }
}

// ---- The alternation ----

// Truth with the free markers 2 cm off and the pots' biases 0.1 off.
Estimate perturbedTruth(const test::ArmProblem& p) {
  Estimate est;
  est.theta = p.truth;
  for (size_t m = 0; m < p.sensors.markers.size(); ++m)
    if (!p.sensors.markers[m].fixed)
      est.theta.marker_position[m] += Eigen::Vector3d(0.02, -0.02, 0);
  for (GainBias& gb : est.theta.joint_sensor) gb.bias += 0.1;
  est.state.q = p.q_true;
  return est;
}

TEST(WideBasinAlternation, ConvergesToTheTruthFromNearIt) {
  ArmSetup s(arm(300));
  const WideBasin wb = s.basin(s.p.seed);
  Estimate est = perturbedTruth(s.p);
  wb.alternate(1.0, 1e-6, &est);
  for (size_t m = 0; m < s.p.sensors.markers.size(); ++m)
    EXPECT_LT((est.theta.marker_position[m] - s.p.truth.marker_position[m]).norm(), 3e-3);
  for (int j = 0; j < 4; ++j) {
    EXPECT_NEAR(est.theta.joint_sensor[j].gain, s.p.truth.joint_sensor[j].gain, 0.03);
    EXPECT_NEAR(est.theta.joint_sensor[j].bias, s.p.truth.joint_sensor[j].bias, 0.03);
  }
  EXPECT_LT(worstRmsError(est.state.q, s.p.q_true), 0.03);
}

TEST(WideBasinAlternation, PotWeightZeroLeavesThePotsOutOfQ) {
  ArmSetup s(arm(300));
  const WideBasin wb = s.basin(s.p.seed);
  Estimate near = perturbedTruth(s.p), far = perturbedTruth(s.p);
  for (GainBias& gb : far.theta.joint_sensor) gb.bias += 5.0, gb.gain *= -2.0;
  wb.alternate(0.0, 1e-6, &near);
  wb.alternate(0.0, 1e-6, &far);
  EXPECT_LT((near.state.q - far.state.q).cwiseAbs().maxCoeff(), 1e-9);
  for (size_t m = 0; m < s.p.sensors.markers.size(); ++m)
    EXPECT_LT((near.theta.marker_position[m] - far.theta.marker_position[m]).norm(), 1e-9);
  // The pots' maps are still fitted, to the markers' q (so with the right
  // signs, though less precisely than with the pots' help).
  for (int j = 0; j < 4; ++j)
    EXPECT_EQ(far.theta.joint_sensor[j].gain > 0, s.p.truth.joint_sensor[j].gain > 0) << j;
}

TEST(WideBasinAlternation, RecheckRightsASignTheMarkersContradict) {
  ArmSetup s(arm(300));
  const WideBasin wb = s.basin(s.p.seed);
  Estimate est = atTheTruth(s.p);
  EXPECT_FALSE(wb.recheckSigns(&est));  // nothing misfits: nothing tried
  // j4 mirrored together with its pot's map (flipSign): the pots fit as
  // before, the markers do not.
  flipSign(wb.guesses()[3], &est.theta, &est.state.q);
  EXPECT_TRUE(wb.recheckSigns(&est));
  EXPECT_EQ(est.theta.joint_sensor[3].gain, s.p.truth.joint_sensor[3].gain);
  // A move the refinement on the subsample would right by itself may be
  // kept too; the alternation that follows in run() rights it on every
  // frame.
  // (Thirty iterations at most per alternation; this start takes more.)
  wb.alternate(1.0, 1e-4, &est);
  wb.alternate(1.0, 1e-8, &est);
  for (int j = 0; j < 4; ++j)
    EXPECT_NEAR(est.theta.joint_sensor[j].gain, s.p.truth.joint_sensor[j].gain, 0.03) << j;
  EXPECT_LT(worstRmsError(est.state.q, s.p.q_true), 0.03);
}

// ---- Jumps between minima after convergence ----

TEST(MinimumMoves, HalfTurnKeepsThePotsPredictions) {
  ArmSetup s(arm(100));
  const WideBasin wb = s.basin(s.p.seed);
  SensorParameters theta = s.p.truth;
  RowMatrix q = s.p.q_true;
  const PotGuess& g = wb.guesses()[2];
  halfTurn(s.p.robot, g, &theta, &q);
  // Toward the middle of j3's limits, by exactly half a turn.
  const double mid = 0.5 * (s.p.robot.lowerLimits()[g.column] + s.p.robot.upperLimits()[g.column]);
  const double shift = q(0, g.column) - s.p.q_true(0, g.column);
  EXPECT_NEAR(std::abs(shift), M_PI, 1e-12);
  EXPECT_LT(std::abs(q.col(g.column).mean() - mid),
            std::abs(s.p.q_true.col(g.column).mean() - mid) + M_PI);
  const GainBias& before = s.p.truth.joint_sensor[g.sensor];
  const GainBias& after = theta.joint_sensor[g.sensor];
  for (int t = 0; t < q.rows(); ++t)
    EXPECT_NEAR(after.gain * q(t, g.column) + after.bias,
                before.gain * s.p.q_true(t, g.column) + before.bias, 1e-12);
}

TEST(MinimumMoves, EveryJumpOfEachGuessAndItsParentButNoneOfAHeldBias) {
  ArmSetup s(arm(100));
  const WideBasin wb = s.basin(s.p.seed);
  // The arm: 4 guesses, 3 of them below another: 4 flips and 4 half turns,
  // per pair a double flip, a wrist flip and a double half turn; the chain
  // flips closed by a joint below (j1 with j2 mirrored and j3, j2 with j3
  // mirrored and j4, j1 with j2 and j3 mirrored and j4), each with its first
  // mirrored joint about zero or over the top, and those that end the chain
  // (j1 with j2..j4, j2 with j3 and j4, j3 with j4), over the top. And the
  // whole robot mirrored, every joint about its zero.
  const std::vector<MinimumMove> moves = minimumMoves(s.p.robot, wb.guesses(), wb.moves());
  EXPECT_EQ(moves.size(), 4u + 4u + 3u * 3u + 3u * 2u + 3u + 1u);
  EXPECT_TRUE(moves.back().flip_about_zero);
  EXPECT_EQ(moves.back().flip, (std::vector<int>{0, 1, 2, 3}));
  EXPECT_EQ(std::count_if(moves.begin(), moves.end(),
                          [](const MinimumMove& m) { return m.flip_about_zero; }),
            1);
  auto count = [&](const MinimumMove& move) {
    return std::count_if(moves.begin(), moves.end(), [&](const MinimumMove& m) {
      return m.flip == move.flip && m.half_turn == move.half_turn;
    });
  };
  EXPECT_EQ(count({{1}, {0, 2}, {}}), 1);
  EXPECT_EQ(count({{1, 2}, {0, 3}, {}}), 1);
  EXPECT_EQ(count({{1, 2}, {0, 1, 3}, {}}), 1);  // over the top, closed
  EXPECT_EQ(count({{1, 2, 3}, {0, 1}, {}}), 1);  // over the top to the end
  EXPECT_EQ(count({{2, 3}, {1, 2}, {}}), 1);
  EXPECT_EQ(count({{1, 2}, {0, 1}, {}}), 0);  // not the end: j4 would stay
  // Marking joints keeps the short moves (all but the 3 over the top
  // closed and the 3 to the chain's end) and the long chain flips that turn
  // or mirror a marked joint: with j4, the 5 that reach it (all but j1 with
  // j2 mirrored over the top, closed by j3).
  std::vector<bool> through(s.p.robot.dof(), false);
  const auto short_moves = minimumMoves(s.p.robot, wb.guesses(), wb.moves(), &through);
  EXPECT_EQ(short_moves.size(), moves.size() - 6u);
  through[wb.guesses()[3].column] = true;
  const auto through_j4 = minimumMoves(s.p.robot, wb.guesses(), wb.moves(), &through);
  EXPECT_EQ(through_j4.size(), short_moves.size() + 5u);
  for (const MinimumMove& m : through_j4) {
    const bool is_short = std::any_of(short_moves.begin(), short_moves.end(), [&](const auto& o) {
      return o.flip == m.flip && o.half_turn == m.half_turn;
    });
    const bool reaches_j4 = std::count(m.flip.begin(), m.flip.end(), 3) +
                            std::count(m.half_turn.begin(), m.half_turn.end(), 3);
    EXPECT_TRUE(is_short || reaches_j4) << m.flip.size() << " mirrored";
  }
  std::vector<PotGuess> held = wb.guesses();
  held[2].bias_held = true;
  for (const MinimumMove& m : minimumMoves(s.p.robot, held, wb.moves()))
    EXPECT_EQ(std::count(m.half_turn.begin(), m.half_turn.end(), 2), 0);
  held[2].fixed = true;  // a held gain: no move touches the guess
  for (const MinimumMove& m : minimumMoves(s.p.robot, held, wb.moves())) {
    EXPECT_EQ(std::count(m.flip.begin(), m.flip.end(), 2), 0);
    EXPECT_EQ(std::count(m.half_turn.begin(), m.half_turn.end(), 2), 0);
  }
}

// A chain flip over the top (minimumMoves): a roll about x half a turn, the
// pitch about y below it mirrored over the top (π − q), the next pitch
// mirrored. R_x(π) R_y(π − q) = R_z(π) R_y(−q), and R_z(π) passes each
// pitch as a mirror and each link offset along z unchanged: the roll's
// link lies where it did turned half a turn about x (its offset to the
// pitch along x), every link below the pitch turned half a turn about its
// own z, so markers re-placed in those links fit exactly as well (a
// finger's roll and two flexions, an arm's shoulder roll, pitch and elbow).
// With an offset off z the last link's origin moves: no exact minimum then.
TEST(MinimumMoves, TheRollFlipTurnsEveryLinkBelowHalfATurnAboutItsOwnZ) {
  const auto chain = [](const std::string& offset) {
    std::string u = R"(<robot name="finger"><link name="base"/><link name="l1"/><link name="l2"/>
      <link name="l3"/>
      <joint name="roll" type="revolute"><parent link="base"/><child link="l1"/>
        <axis xyz="1 0 0"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
      <joint name="pitch1" type="revolute"><parent link="l1"/><child link="l2"/>
        <origin xyz="0.03 0 0"/><axis xyz="0 1 0"/>
        <limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
      <joint name="pitch2" type="revolute"><parent link="l2"/><child link="l3"/>
        <origin xyz="OFFSET"/><axis xyz="0 1 0"/>
        <limit lower="-3" upper="3" effort="1" velocity="1"/></joint></robot>)";
    u.replace(u.find("OFFSET"), 6, offset);
    return RobotModel::fromString(u, "finger");
  };
  const Eigen::Vector3d q(0.4, -0.7, 0.9);
  const Eigen::Vector3d flipped(q[0] + M_PI, M_PI - q[1], -q[2]);
  const Eigen::Isometry3d half_x(Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()));
  const Eigen::Isometry3d half_z(Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitZ()));
  for (const bool on_z : {true, false}) {
    const RobotModel robot = chain(on_z ? "0 0 -0.04" : "0.02 0 -0.04");
    KinematicsWorkspace a(robot), b(robot);
    forwardKinematics(robot, q, &a);
    forwardKinematics(robot, flipped, &b);
    for (const char* name : {"l1", "l2", "l3"}) {
      const int l = *robot.linkIndex(name);
      const Eigen::Isometry3d& turn = std::string(name) == "l1" ? half_x : half_z;
      const Eigen::Matrix4d expected = (a.link_pose[l] * turn).matrix();
      const double off = (b.link_pose[l].matrix() - expected).norm();
      if (on_z || std::string(name) != "l3")
        EXPECT_LT(off, 1e-12) << name;
      else
        EXPECT_GT(off, 1e-3) << "an offset off z moves the last link";
    }
  }
}

// The whole-robot mirror negates every joint's angle (about its zero: the
// arm's limits are symmetric) and every pot's gain, so that every pot
// predicts what it did.
TEST(MinimumMoves, TheWholeRobotMirrorNegatesEveryAngleAndKeepsThePotsPredictions) {
  ArmSetup s(arm(100));
  const WideBasin wb = s.basin(s.p.seed);
  const MinimumMove mirror = minimumMoves(s.p.robot, wb.guesses(), wb.moves()).back();
  ASSERT_TRUE(mirror.flip_about_zero);
  Estimate est = atTheTruth(s.p);
  applyMove(s.p.robot, wb.guesses(), mirror, &est.theta, &est.state.q);
  EXPECT_LT((est.state.q + s.p.q_true).cwiseAbs().maxCoeff(), 1e-12);
  for (int j = 0; j < 4; ++j) {
    const GainBias& was = s.p.truth.joint_sensor[j];
    const GainBias& now = est.theta.joint_sensor[j];
    EXPECT_NEAR(now.gain, -was.gain, 1e-12) << j;
    EXPECT_NEAR(now.gain * est.state.q(7, j) + now.bias, was.gain * s.p.q_true(7, j) + was.bias,
                1e-12) << j;
  }
}

// The arm's j3 half a turn off and j4 mirrored, the pots' maps along (the
// arm4/partial miss of the basin test): every pot still fits, the markers
// a little worse. The jump back is found; from the truth there is none.
TEST(WideBasinAfterConvergence, JumpsBackFromAWristFlip) {
  ArmSetup s(arm(300));
  const WideBasin wb = s.basin(s.p.seed);
  Estimate est = atTheTruth(s.p);
  EXPECT_FALSE(wb.jumpToBetterMinimum(&est));
  const MinimumMove wrist_flip{{3}, {2}, {}};
  applyMove(s.p.robot, wb.guesses(), wrist_flip, &est.theta, &est.state.q);
  ASSERT_NE(est.theta.joint_sensor[3].gain, s.p.truth.joint_sensor[3].gain);
  const auto jump = wb.jumpToBetterMinimum(&est);
  ASSERT_TRUE(jump);
  for (int j = 0; j < 4; ++j) {
    EXPECT_NEAR(est.theta.joint_sensor[j].gain, s.p.truth.joint_sensor[j].gain, 1e-9) << j;
    EXPECT_NEAR(est.theta.joint_sensor[j].bias, s.p.truth.joint_sensor[j].bias, 1e-9) << j;
  }
  EXPECT_LT(worstRmsError(est.state.q, s.p.q_true), 1e-9);
}

// Guess g's pot map and its joint's motion `turns` whole turns off: every
// reading fitted as before.
void turnOff(const PotGuess& g, double turns, Estimate* est) {
  const double turn = 2 * M_PI * turns;
  est->state.q.col(g.column).array() += turn;
  est->theta.joint_sensor[g.sensor].bias -= turn * est->theta.joint_sensor[g.sensor].gain;
}

// j1's pot map a whole turn off, its motion with it: every angle a turn
// below j1's limits (±1.5, less than a turn apart), every reading fitted
// exactly as at the truth (the arm4/partial misses of the basin test, at
// the truth's cost). The jump back into the limits is found.
TEST(WideBasinAfterConvergence, JumpsBackFromAMotionATurnOutsideTheLimits) {
  ArmSetup s(arm(300));
  const WideBasin wb = s.basin(s.p.seed);
  Estimate est = atTheTruth(s.p);
  const PotGuess& g = wb.guesses()[0];
  ASSERT_EQ(g.column, 0);
  ASSERT_LT(s.p.robot.upperLimits()[0] - s.p.robot.lowerLimits()[0], 2 * M_PI);
  turnOff(g, -1, &est);
  const auto jump = wb.jumpToBetterMinimum(&est);
  ASSERT_TRUE(jump);
  EXPECT_EQ(jump->whole_turn, std::vector<int>{0});
  for (int j = 0; j < 4; ++j)
    EXPECT_NEAR(est.theta.joint_sensor[j].bias, s.p.truth.joint_sensor[j].bias, 1e-9) << j;
  EXPECT_LT(worstRmsError(est.state.q, s.p.q_true), 1e-9);
}

// Jumps refined to one minimum by different paths differ by rounding; of
// those, the one whose start fits best is taken, the whole log going on
// from that start (a whole turn, not a mirror-and-place that refined 6e-7
// lower: an unseen Go2's thigh, whose run from the mirror on the whole log
// ended elsewhere); of starts alike, the first listed. A clearly lower
// refined cost wins whatever its start.
TEST(JumpChoice, OfJumpsThatFitAlikeTheNearestStartIsTakenAndAClearlyBetterOneWins) {
  const double base = 1000, refined = 0.99 * base, rounding = 0.25 * kSameRefinedFit;
  JumpChoice better(base);
  better.consider(0, refined, 2 * base, true);
  better.consider(1, refined * (1 - rounding), 3 * base, true);  // lower, farther start
  EXPECT_EQ(better.chosen(), 0);
  better.consider(2, refined * (1 + rounding), base, false);  // higher, nearer start
  EXPECT_EQ(better.chosen(), 2);
  better.consider(3, refined, base * (1 - 0.5 * kSameStart), false);  // starts alike
  EXPECT_EQ(better.chosen(), 2);
  better.consider(4, refined * (1 - 2 * kSameRefinedFit), 9 * base, false);  // clearly lower
  EXPECT_EQ(better.chosen(), 4);
  better.consider(5, base, base, true);  // only within: a better one is held
  EXPECT_EQ(better.chosen(), 4);

  JumpChoice within(base);
  const double as_well = base * (1 + 0.5 * kSameFit);
  within.consider(0, as_well, base, false);  // relieves nothing
  EXPECT_EQ(within.chosen(), -1);
  within.consider(1, base * (1 + 2 * kSameFit), base, true);  // fits worse
  EXPECT_EQ(within.chosen(), -1);
  within.consider(2, as_well, 2 * base, true);
  EXPECT_EQ(within.chosen(), 2);
  within.consider(3, as_well * (1 - rounding), 3 * base, true);
  EXPECT_EQ(within.chosen(), 2);
  within.consider(4, as_well * (1 + rounding), base, true);
  EXPECT_EQ(within.chosen(), 4);
  within.consider(5, kBetterMinimum * base * 0.999, 9 * base, false);  // better than the base
  EXPECT_EQ(within.chosen(), 5);
}

// Where the verdict would flag a motion beyond its limits, a relieving
// jump that fits the subsample within kFlaggedSameFit goes on to the whole
// log (a near-exact mirror can fit 150 frames better than the truth does);
// elsewhere only within kSameFit.
TEST(JumpChoice, AJumpOutOfAFlaggedMotionMayFitTheSubsampleALittleWorse) {
  const double base = 1000, worse = base * (1 + 0.5 * kFlaggedSameFit);
  ASSERT_GT(worse, (1 + kSameFit) * base);
  JumpChoice unflagged(base);
  unflagged.consider(0, worse, worse, true);
  EXPECT_EQ(unflagged.chosen(), -1);
  JumpChoice flagged(base, kFlaggedSameFit);
  flagged.consider(0, worse, worse, false);  // relieves nothing
  EXPECT_EQ(flagged.chosen(), -1);
  flagged.consider(1, base * (1 + 2 * kFlaggedSameFit), base, true);  // too much worse
  EXPECT_EQ(flagged.chosen(), -1);
  flagged.consider(2, worse, worse, true);
  EXPECT_EQ(flagged.chosen(), 2);
}

// Alike is measured from the lowest refined cost: a chain of jumps each
// alike to the one before, its starts ever nearer, does not drift above it.
TEST(JumpChoice, AlikeIsMeasuredFromTheLowestCost) {
  const double base = 1000, refined = 0.99 * base;
  JumpChoice chain(base);
  chain.consider(0, refined, 3 * base, true);
  chain.consider(1, refined * (1 + 0.9 * kSameRefinedFit), 2 * base, true);
  chain.consider(2, refined * (1 + 1.8 * kSameRefinedFit), base, true);
  EXPECT_EQ(chain.chosen(), 1);
}

// Three pots' maps a whole turn off, their motions with them (an unseen
// UR10's five, one per jump round, ran out of rounds): one jump turns them
// all back.
TEST(WideBasinAfterConvergence, JumpsBackFromSeveralMotionsATurnOutsideTheLimitsAtOnce) {
  ArmSetup s(arm(300));
  const WideBasin wb = s.basin(s.p.seed);
  Estimate est = atTheTruth(s.p);
  for (int i : {0, 1, 3}) turnOff(wb.guesses()[i], i == 1 ? 1 : -1, &est);
  const auto jump = wb.jumpToBetterMinimum(&est);
  ASSERT_TRUE(jump);
  EXPECT_EQ(jump->whole_turn, (std::vector<int>{0, 1, 3}));
  for (int j = 0; j < 4; ++j)
    EXPECT_NEAR(est.theta.joint_sensor[j].bias, s.p.truth.joint_sensor[j].bias, 1e-9) << j;
  EXPECT_LT(worstRmsError(est.state.q, s.p.q_true), 1e-9);
}

// j1 a whole turn off as above, and j3's URDF limits narrowed to the
// bottom 0.1 rad of its true motion, which so rests beyond them in most
// frames (limits narrower than the robot's): both motions are mostly at
// their limits, and the whole turns of both are tried together first, but
// j3 turned rests beyond the other limit and fits worse there (the jumps'
// refinement holds the angles within the limits), so only j1 is turned.
TEST(WideBasinAfterConvergence, AMotionRestingBeyondItsLimitsIsNotTurnedWithTheOthers) {
  test::ArmProblem p = arm(300);
  const double lo = p.q_true.col(2).minCoeff();
  std::string urdf = test::kArmUrdf;
  const std::string j3_limits = R"(<axis xyz="1 0 0"/><limit lower="-1.2" upper="1.2")";
  const size_t at = urdf.find(j3_limits);
  ASSERT_NE(at, std::string::npos);
  urdf.replace(at, j3_limits.size(),
               R"(<axis xyz="1 0 0"/><limit lower=")" + std::to_string(lo) + R"(" upper=")" +
                   std::to_string(lo + 0.1) + R"(")");
  p.robot = RobotModel::fromString(urdf, "arm4_narrow_j3");
  ArmSetup s(std::move(p));
  const WideBasin wb = s.basin(s.p.seed);
  Estimate est = atTheTruth(s.p);
  turnOff(wb.guesses()[0], -1, &est);
  const auto jump = wb.jumpToBetterMinimum(&est);
  ASSERT_TRUE(jump);
  EXPECT_EQ(jump->whole_turn, std::vector<int>{0});
  EXPECT_LT(worstRmsError(est.state.q, s.p.q_true), 1e-9);
}

// The arm with j4 continuous (its motion, within ±1.2, unchanged).
test::ArmProblem continuousWristArm(int frames) {
  test::ArmProblem p = arm(frames);
  p.robot = RobotModel::fromString(test::armUrdfWithContinuousJoint("j4"), "arm4_continuous_wrist");
  return p;
}

// The truth with guess g's pot map at an eighth of its gain, the frames'
// angles with it, spread over 8 times the motion.
Estimate spreadEightfold(const test::ArmProblem& p, const PotGuess& g) {
  Estimate est = atTheTruth(p);
  GainBias& map = est.theta.joint_sensor[g.sensor];
  const double mean = p.q_true.col(g.column).mean();
  est.state.q.col(g.column) = (mean + 8 * (p.q_true.col(g.column).array() - mean)).matrix();
  map.bias += map.gain * mean * (1 - 1.0 / 8);
  map.gain /= 8;
  return est;
}

// The jump from est is j4's wrap, and it finds j4's pot map again (its bias
// modulo a turn of the joint).
void expectTheWrapFindsTheMap(const test::ArmProblem& p, const WideBasin& wb, Estimate* est) {
  const PotGuess& g = wb.guesses()[3];
  const auto jump = wb.jumpToBetterMinimum(est);
  ASSERT_TRUE(jump);
  EXPECT_EQ(jump->wrap, std::vector<int>{3});
  const GainBias& map = est->theta.joint_sensor[g.sensor];
  const GainBias& truth = p.truth.joint_sensor[g.sensor];
  EXPECT_NEAR(map.gain, truth.gain, 0.02 * std::abs(truth.gain));
  EXPECT_NEAR(std::remainder(map.bias - truth.bias, 2 * M_PI * truth.gain), 0.0, 0.05);
}

// The arm with j4 continuous (its motion, within ±1.2, unchanged): j4's pot
// map at an eighth of its gain, the frames' angles with it, spread over
// 8 times the motion (several turns), each a turn or more from where the
// markers put it (the unseen TIAGo wheel's miss of the basin test). The
// wrap gathers them into one turn and finds the map again; a joint with
// limits under a turn, or a motion within one, is offered no wrap.
TEST(WideBasinAfterConvergence, WrapsAContinuousJointsMotionSpreadOverTurns) {
  ArmSetup s(continuousWristArm(300));
  const WideBasin wb = s.basin(s.p.seed);
  ASSERT_EQ(wb.guesses()[3].column, 3);
  EXPECT_TRUE(wrapMoves(s.p.robot, wb.guesses(), s.p.q_true).empty());
  Estimate est = spreadEightfold(s.p, wb.guesses()[3]);
  const std::vector<MinimumMove> wraps = wrapMoves(s.p.robot, wb.guesses(), est.state.q);
  ASSERT_EQ(wraps.size(), 1u);
  EXPECT_EQ(wraps[0].wrap, std::vector<int>{3});
  expectTheWrapFindsTheMap(s.p, wb, &est);
  // The same arm as the fixture builds it (j4 within ±1.2): no wrap.
  EXPECT_TRUE(wrapMoves(arm(10).robot, wb.guesses(), est.state.q * 8).empty());
}

// The same wrap from a log whose frames carry the damping of a long run
// (large: steps tiny): the jump is judged on the subsample, whose frames
// start afresh, and the full log must land where it did. With the damping
// carried, ur5 on partial swings (basin truth 4) had its wrist's frames
// left elsewhere, the turn cut inside the motion, the pot's map at -0.5x
// the truth's gain, flagged.
TEST(WideBasinAfterConvergence, AWrapLandsAlikeWhateverDampingTheFramesCarry) {
  ArmSetup s(continuousWristArm(300));
  const WideBasin wb = s.basin(s.p.seed);
  ASSERT_EQ(wb.guesses()[3].column, 3);
  Estimate est = spreadEightfold(s.p, wb.guesses()[3]);
  est.state.lambda = Eigen::VectorXd::Constant(est.state.q.rows(), 1e6);
  expectTheWrapFindsTheMap(s.p, wb, &est);
}

// A wrap keeps a motion that spans less than a turn whole: it cuts the
// turn where no angle lies. The arm's j4 made continuous, its motion over
// 5.9 rad (most of it near the lower end), each frame's angle a turn off or
// not (right modulo a turn, as where the markers fit every frame): the
// wrapped column is the motion itself, moved by one whole number of turns.
// (Cut about the angles' circular mean, the turn ended at +2.0, and the
// frames beyond it stayed a turn off.)
TEST(WideBasinAfterConvergence, AWrapCutsTheTurnWhereNoAngleLies) {
  ArmSetup s(continuousWristArm(300));
  const WideBasin wb = s.basin(s.p.seed);
  ASSERT_EQ(wb.guesses()[3].column, 3);
  RowMatrix q = s.p.q_true;
  const int T = static_cast<int>(q.rows());
  Eigen::VectorXd motion(T);
  for (int t = 0; t < T; ++t) {
    const double u = static_cast<double>(t) / (T - 1);
    motion[t] = -2.0 + 5.9 * u * u * u;
    q(t, 3) = motion[t] + 2 * M_PI * (t % 3 - 1);
  }
  MinimumMove move;
  move.wrap = {3};
  SensorParameters theta = s.p.truth;
  applyMove(s.p.robot, wb.guesses(), move, &theta, &q);
  const double turns = (q(0, 3) - motion[0]) / (2 * M_PI);
  EXPECT_NEAR(turns, std::round(turns), 1e-9);
  for (int t = 0; t < T; ++t) EXPECT_NEAR(q(t, 3) - motion[t], q(0, 3) - motion[0], 1e-9) << t;
}

// ---- The whole initialisation ----

TEST(WideBasinInitialisation, ArmFromThePapersSeedingLandsNearTheTruth) {
  ArmSetup s(arm(500));
  QState state;
  state.q = neutralPose(s.p.robot).transpose().replicate(s.p.obs.num_frames, 1);
  const SensorParameters theta = wideBasinInitialisation(
      s.model, s.p.obs, s.noise, s.loss, kThreads, &s.ws, s.p.seed, &state, true);
  for (int j = 0; j < 4; ++j) {
    const GainBias& truth = s.p.truth.joint_sensor[j];
    EXPECT_NEAR(theta.joint_sensor[j].gain, truth.gain, 0.05 * std::abs(truth.gain)) << j;
  }
  const Eigen::AngleAxisd err(theta.mocap.rotation * s.p.truth.mocap.rotation.inverse());
  EXPECT_LT(err.angle(), 0.02);
  EXPECT_LT((theta.mocap.translation - s.p.truth.mocap.translation).norm(), 0.01);
  EXPECT_LT(worstRmsError(state.q, s.p.q_true), 0.03);
}

TEST(WideBasinInitialisation, GimbalWithoutPotsTracksFromTheNeutralPose) {
  const RobotModel robot = RobotModel::fromFile(test::dataPath("gimbal2.urdf"));
  const SensorsFile seed = loadSensorsFile(test::dataPath("gimbal2_seed.yaml"), robot);
  const SensorsFile truth = loadSensorsFile(test::dataPath("gimbal2_truth.yaml"), robot);
  const MeasurementModel model(robot, seed.sensors);
  SimulationOptions so;
  so.frames = 300;
  so.seed = 3;
  const Simulation sim = simulate(model, truth.theta, so);
  const Observations obs = bindLog(sim.data.log, seed.sensors, "seed", 1.0);
  const NoiseModel noise = NoiseModel::fromSeeds(seed.sensors);
  const RobustLoss loss;
  std::vector<FrameWorkspace> ws;
  for (int i = 0; i < kThreads; ++i) ws.emplace_back(model);
  const WideBasin wb(model, obs, noise, loss, kThreads, &ws, seed.theta, true);
  EXPECT_TRUE(wb.guesses().empty());
  QState state;
  state.q = neutralPose(robot).transpose().replicate(obs.num_frames, 1);
  const SensorParameters theta = wb.run(&state);
  const Eigen::AngleAxisd err(theta.mocap.rotation * truth.theta.mocap.rotation.inverse());
  EXPECT_LT(err.angle(), 0.02);
  EXPECT_LT(worstRmsError(state.q, sim.q), 0.03);
  for (size_t k = 0; k < truth.theta.tendon_sensor.size(); ++k) {
    const GainBias& t = truth.theta.tendon_sensor[k];
    EXPECT_NEAR(theta.tendon_sensor[k].gain, t.gain, 0.05 * std::abs(t.gain)) << k;
  }
}

}  // namespace
}  // namespace stac
