// `fixed` lists against simulated truth: a joint sensor's gain or bias held
// (an encoder that reads radians: `fixed: [gain]` with gain 1.0), the mocap
// rotation held, with every method that applies. The held part comes back
// exactly; the free part lands within its reported standard deviation. Also:
// holding a joint's bias removes its gauge with the mocap rotation, the
// classical regression's tied (a, c) column, and stac_calib's exit code for
// an invalid list.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

#include "methods/classical.hpp"
#include "methods/wide_basin.hpp"
#include "model/frame_jacobian.hpp"
#include "stac/calibrate.hpp"
#include "support/arm_files.hpp"
#include "support/arm_fixture.hpp"
#include "support/test_util.hpp"

namespace stac {
namespace {

constexpr int kPot = 1;  // j2_pot: the sensor whose gain or bias is held

// The arm with j2_pot's truth changed to `truth` (readings simulated again)
// and the parts in `fixed` held at their true values.
test::ArmProblem armWithHeldPot(const GainBias& truth, const FixedGainBias& fixed) {
  test::ArmProblem p = test::makeArmProblem(400, 17, 0.3);
  p.truth.joint_sensor[kPot] = truth;
  p.sensors.joint_sensors[kPot].fixed = fixed;
  if (fixed.gain) p.seed.joint_sensor[kPot].gain = truth.gain;
  if (fixed.bias) p.seed.joint_sensor[kPot].bias = truth.bias;
  std::mt19937 rng(5);
  test::simulateReadings(MeasurementModel(p.robot, p.sensors), p.truth, p.q_true, 0.3, 0.0, rng,
                         &p.obs);
  return p;
}

// A "manual calibration" for the baselines: the truth off by a little in
// every free entry (up to half its typical scale), the held ones as given.
SensorParameters nearSeed(const test::ArmProblem& p) {
  const ThetaSpace space(p.sensors);
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const Eigen::VectorXd scale = space.scale(p.truth);
  Eigen::VectorXd d(space.freeSize());
  for (int i = 0; i < space.freeSize(); ++i) d[i] = 0.5 * u(rng) * scale[space.freeIndex()[i]];
  return space.plusFree(p.truth, d);
}

CalibrationOptions optionsFor(Method m, const test::ArmProblem& p) {
  CalibrationOptions o;
  o.method = m;
  o.threads = 2;
  if (m == Method::kEkf) {
    o.ekf.initial_q = p.q_true.row(0).transpose();
    o.ekf.iterations = 3;
  }
  return o;
}

CalibrationResult calibrateWith(Method m, const test::ArmProblem& p) {
  const bool baseline = m == Method::kEkf || m == Method::kClassical;
  return calibrate(p.robot, p.sensors, baseline ? nearSeed(p) : p.seed, p.obs, optionsFor(m, p));
}

// |estimate - truth| within k reported standard deviations (finite, > 0).
void expectWithinStd(double estimate, double truth, double sd, const char* what, double k = 4.0) {
  EXPECT_TRUE(std::isfinite(sd) && sd > 0) << what << " std " << sd;
  EXPECT_LT(std::abs(estimate - truth), k * sd) << what << ": " << estimate << " vs " << truth
                                                << " (std " << sd << ")";
}

std::string methodName(const ::testing::TestParamInfo<Method>& info) {
  static const char* const kNames[] = {"stac", "joint", "ekf", "classical"};
  return kNames[static_cast<int>(info.param)];
}

class HeldPart : public ::testing::TestWithParam<Method> {};
INSTANTIATE_TEST_SUITE_P(FixedList, HeldPart,
                         ::testing::Values(Method::kStac, Method::kMonolithic, Method::kEkf,
                                           Method::kClassical),
                         methodName);

// The classical regression reads every angle off its pot as if exact, so
// its std leaves out the pots' noise: on this arm j2_pot's bias lands ~5 of
// them off with nothing held as with its gain held. Wider for it alone.
double stdsFor(Method m) { return m == Method::kClassical ? 8.0 : 4.0; }

TEST_P(HeldPart, GainHeldAtOneFitsTheBias) {
  const test::ArmProblem p = armWithHeldPot({1.0, 0.37}, {true, false});
  const CalibrationResult r = calibrateWith(GetParam(), p);
  EXPECT_EQ(r.theta.joint_sensor[kPot].gain, 1.0);
  EXPECT_EQ(r.std.joint_sensor[kPot].gain, 0.0);
  expectWithinStd(r.theta.joint_sensor[kPot].bias, 0.37, r.std.joint_sensor[kPot].bias, "bias",
                  stdsFor(GetParam()));
  // The other pots are still fitted.
  expectWithinStd(r.theta.joint_sensor[2].gain, p.truth.joint_sensor[2].gain,
                  r.std.joint_sensor[2].gain, "j3 gain", stdsFor(GetParam()));
}

TEST_P(HeldPart, BiasHeldFitsTheGain) {
  const test::ArmProblem p = armWithHeldPot({-1.6, 0.37}, {false, true});
  const CalibrationResult r = calibrateWith(GetParam(), p);
  EXPECT_EQ(r.theta.joint_sensor[kPot].bias, 0.37);
  EXPECT_EQ(r.std.joint_sensor[kPot].bias, 0.0);
  expectWithinStd(r.theta.joint_sensor[kPot].gain, -1.6, r.std.joint_sensor[kPot].gain, "gain",
                  stdsFor(GetParam()));
}

TEST_P(HeldPart, MocapRotationHeldFitsTheTranslation) {
  test::ArmProblem p = test::makeArmProblem(400, 17, 0.3);
  p.sensors.mocap_frame_fixed = {true, false};
  p.seed.mocap.rotation = p.truth.mocap.rotation;
  const CalibrationResult r = calibrateWith(GetParam(), p);
  EXPECT_TRUE(r.theta.mocap.rotation.coeffs() == p.truth.mocap.rotation.coeffs())
      << r.theta.mocap.rotation.coeffs().transpose();
  EXPECT_EQ(r.std.mocap_rotation, Eigen::Vector3d::Zero());
  for (int i = 0; i < 3; ++i)
    expectWithinStd(r.theta.mocap.translation[i], p.truth.mocap.translation[i],
                    r.std.mocap_translation[i], "translation", stdsFor(GetParam()));
}

// The wide-basin start: a held gain is a known scale that no sweep changes;
// a held bias makes the map q = alpha (p - bias), and a sign flip keeps it.
TEST(FixedList, PotGuessesKeepTheHeldPart) {
  test::ArmProblem p = armWithHeldPot({1.0, 0.37}, {true, false});
  std::vector<PotGuess> guesses = makePotGuesses(p.robot, p.sensors, p.seed, p.obs);
  ASSERT_EQ(guesses.size(), 4u);
  EXPECT_TRUE(guesses[kPot].fixed);
  EXPECT_FALSE(guesses[kPot].bias_held);
  EXPECT_EQ(guesses[kPot].map.alpha, 1.0);
  const Candidate c = guessedMaps(guesses);
  EXPECT_EQ(scaled(c, guesses, 0.5).maps[kPot].alpha, 1.0);
  EXPECT_EQ(withSigns(c, guesses, std::vector<bool>(4, true)).maps[kPot].alpha, 1.0);
  EXPECT_NE(scaled(c, guesses, 0.5).maps[0].alpha, c.maps[0].alpha);

  p = armWithHeldPot({-1.6, 0.37}, {false, true});
  guesses = makePotGuesses(p.robot, p.sensors, p.seed, p.obs);
  ASSERT_EQ(guesses.size(), 4u);
  EXPECT_FALSE(guesses[kPot].fixed);
  EXPECT_TRUE(guesses[kPot].bias_held);
  Candidate exact = guessedMaps(guesses);
  exact.maps[kPot].alpha = 1.0 / -1.6;
  RowMatrix q = p.q_true;
  applyCandidate(guesses, exact, p.obs, &q);
  for (int t = 0; t < p.obs.num_frames; ++t)
    EXPECT_NEAR(q(t, kPot), (p.obs.joint(t, kPot) - 0.37) / -1.6, 1e-12);
  SensorParameters theta = p.truth;
  flipSign(guesses[kPot], &theta, &q);
  EXPECT_EQ(theta.joint_sensor[kPot].bias, 0.37);
  EXPECT_EQ(theta.joint_sensor[kPot].gain, 1.6);
  EXPECT_NEAR(q(7, kPot), -(p.obs.joint(7, kPot) - 0.37) / -1.6, 1e-12);
}

// m_base free: the mocap rotation about j1's axis trades off with j1's bias
// (Stac.FreeBaseMarkerIsReportedUnidentifiable). Holding that bias removes
// the gauge; the rotation is then determined.
TEST(FixedList, HeldBiasRemovesItsGaugeWithTheMocapRotation) {
  test::ArmProblem p = test::makeArmProblem(300, 8);
  p.sensors.markers[0].fixed = false;
  p.seed.marker_position[0].setZero();
  p.sensors.joint_sensors[0].fixed = {false, true};
  p.seed.joint_sensor[0].bias = p.truth.joint_sensor[0].bias;
  CalibrationOptions o;
  o.threads = 2;
  const CalibrationResult r = calibrate(p.robot, p.sensors, p.seed, p.obs, o);
  EXPECT_TRUE(r.summary.unidentifiable.empty()) << r.summary.unidentifiable.front().reason;
  EXPECT_EQ(r.theta.joint_sensor[0].bias, p.truth.joint_sensor[0].bias);
  const Eigen::AngleAxisd err(r.theta.mocap.rotation * p.truth.mocap.rotation.inverse());
  EXPECT_TRUE(std::isfinite(r.std.mocap_rotation.norm()));
  EXPECT_LT(err.angle(), 4.0 * r.std.mocap_rotation.norm());
  for (int i = 0; i < 3; ++i)
    expectWithinStd(r.theta.marker_position[0][i], p.truth.marker_position[0][i],
                    r.std.marker_position[0][i], "m_base");
}

// With the bias b held the regression's c is tied to a (c = -b a), so that
// a's column is the derivative along (1, -b) in (a, c).
TEST(FixedList, ClassicalTiedColumnMatchesCentralDifferences) {
  test::ArmProblem p = test::makeArmProblem(5, 7);
  p.sensors.joint_sensors[kPot].fixed = {false, true};
  const MeasurementModel model(p.robot, p.sensors);
  const NoiseModel noise = NoiseModel::fromSeeds(p.sensors);
  const RobustLoss loss(LossKind::kNone, 1.0);
  const JointSources sources = findJointSources(p.robot, p.sensors);
  ClassicalParameters cp;
  cp.theta = p.truth;
  for (const GainBias& gb : p.truth.joint_sensor) cp.inverse.push_back(inverseMap(gb));
  const FrameReadings fr = frameReadings(p.obs, 2);
  FrameWorkspace ws(model);
  Eigen::VectorXd r;
  Eigen::MatrixXd J;
  ASSERT_TRUE(classicalFrame(model, sources, cp, noise, loss, fr, &ws, &r, &J));
  const double b = p.truth.joint_sensor[kPot].bias, h = 1e-6;
  auto residual = [&](double e) {
    ClassicalParameters c = cp;
    c.inverse[kPot].a += e;
    c.inverse[kPot].c -= b * e;
    FrameWorkspace w(model);
    Eigen::VectorXd rr;
    classicalFrame(model, sources, c, noise, loss, fr, &w, &rr, nullptr);
    return rr;
  };
  const Eigen::VectorXd fd = (residual(h) - residual(-h)) / (2 * h);
  const int o = model.thetaSpace().jointOffset(kPot);
  EXPECT_GT(fd.norm(), 1.0);
  EXPECT_LT((fd - J.col(o)).norm(), 1e-5 * fd.norm());
}

TEST(FixedList, CalibExitsWithTwoOnAnInvalidList) {
  test::TempDir dir;
  test::writeFile(dir.file("arm.urdf"), test::kArmUrdf);
  test::writeFile(dir.file("truth.yaml"), test::kArmTruth);
  std::string seed = test::kArmSeed;
  const std::string pot = "{name: j2_pot, joint: j2}";
  seed.replace(seed.find(pot), pot.size(), "{name: j2_pot, joint: j2, fixed: [rotation]}");
  test::writeFile(dir.file("bad.yaml"), seed);
  const std::string urdf = " --urdf " + dir.file("arm.urdf");
  ASSERT_EQ(test::runCommand(test::appPath("stac_simulate") + urdf + " --sensors " +
                             dir.file("truth.yaml") + " --frames 50 --log " +
                             dir.file("data.csv") + " --seed 4")
                .exit_code,
            0);
  const auto r = test::runCommand(test::appPath("stac_calib") + urdf + " --log " +
                                  dir.file("data.csv") + " --sensors " + dir.file("bad.yaml") +
                                  " --output " + dir.file("out.yaml"));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find(dir.file("bad.yaml") + ":11:"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("joint_sensors[1].fixed"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("a joint sensor has no rotation"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace stac
