// Variance adaptation (noise_adaptation.hpp): the estimate of a long log's
// group is its residuals' mean square per residual dof; a group with no
// residual dof left (the q_t fit it exactly) stays at its seed instead of
// collapsing; θ's free entries count against the group they shape; under a
// robust loss gross errors do not inflate σ (the taper).
#include "solve/noise_adaptation.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "stac/calibrate.hpp"
#include "stac/sensors_file.hpp"
#include "stac/simulate.hpp"
#include "stac/theta_space.hpp"
#include "support/arm_files.hpp"
#include "support/arm_fixture.hpp"

namespace stac {
namespace {

TEST(NoiseAdaptation, LongLogGroupTakesItsResidualsMeanSquare) {
  GroupResiduals r;
  r.wsse[0] = 4.0 * 1e6;  // κ² = 4 over a million residual dof
  r.dofs[0] = 1e6;
  GroupScales scales;
  updateScales(r, false, &scales);
  EXPECT_NEAR(scales.kappa[0], 2.0, 1e-4);
  EXPECT_EQ(scales.kappa[1], 1.0);  // no rows: unchanged
}

TEST(NoiseAdaptation, GroupFitExactlyDoesNotCollapse) {
  // A group the q_t fit exactly: nearly no residual, nearly no dof left.
  // Without the seed's weight, κ = sqrt(1e-8 / 1) = 1e-4 and, iterated, σ
  // drifts to 0; with it κ stays near its seed.
  GroupResiduals r;
  r.wsse[0] = 1e-8;
  r.dofs[0] = 1.0;
  GroupScales scales;
  for (int it = 0; it < 50; ++it) updateScales(r, true, &scales);
  EXPECT_GT(scales.kappa[0], 0.9);
  EXPECT_LE(scales.kappa[0], 1.0);
}

TEST(NoiseAdaptation, FreeThetaEntriesCountAgainstTheirGroup) {
  test::ArmProblem p = test::makeArmProblem(5, 1);
  SensorSet s = p.sensors;
  ASSERT_GE(s.markers.size(), 2u);
  ASSERT_GE(s.joint_sensors.size(), 2u);
  for (auto& m : s.markers) m.fixed = false;
  for (auto& j : s.joint_sensors) j.fixed = FixedGainBias::both(false);
  for (auto& t : s.tendon_sensors) t.fixed = FixedGainBias::both(false);
  s.mocap_frame_fixed = FixedFrame::both(false);
  const int M = static_cast<int>(s.markers.size());
  const int J = static_cast<int>(s.joint_sensors.size());
  const int N = static_cast<int>(s.tendon_sensors.size());
  EXPECT_EQ(ThetaSpace(s).freeInGroup(SensorGroup::kMarker), 6 + 3 * M);
  EXPECT_EQ(ThetaSpace(s).freeInGroup(SensorGroup::kJoint), 2 * J);
  EXPECT_EQ(ThetaSpace(s).freeInGroup(SensorGroup::kTendon), 2 * N);
  s.markers[0].fixed = true;
  s.mocap_frame_fixed.rotation = true;
  s.joint_sensors[1].fixed.gain = true;
  EXPECT_EQ(ThetaSpace(s).freeInGroup(SensorGroup::kMarker), 3 + 3 * (M - 1));
  EXPECT_EQ(ThetaSpace(s).freeInGroup(SensorGroup::kJoint), 2 * J - 1);
}

// The taper's constants against χ²_k drawn: b is 4 times the 99% quantile,
// and mean_share the tapered mean's share of the plain one.
TEST(NoiseAdaptation, ScaleTaperConstantsMatchTheChiSquare) {
  std::mt19937_64 rng(5);
  for (int k = 1; k <= 3; ++k) {
    const ScaleTaper taper = scaleTaper(k);
    std::chi_squared_distribution<double> chi2(k);
    const int n = 400000;
    double below = 0, phi_s = 0, phi = 0;
    for (int i = 0; i < n; ++i) {
      const double s = chi2(rng);
      below += s <= taper.bound / 4;
      phi_s += taper.weight(s) * s;
      phi += taper.weight(s);
    }
    EXPECT_NEAR(below / n, 0.99, 0.001) << k;
    EXPECT_NEAR(phi_s / (k * phi), taper.mean_share, 0.004) << k;
  }
  EXPECT_EQ(scaleTaper(1).weight(scaleTaper(1).bound), 0.0);
  EXPECT_EQ(scaleTaper(1).weight(0.0), 1.0);
}

// 5% of the readings gross (pots and tendon at 50-200 σ, markers 5-30 cm)
// under a Huber loss: σ adapted from the truth's stays near the truth's
// (Σ w s made it 6x for the markers, 24x for the pots). The pots' share
// stays a little high: the q_t of joints their pots alone determine follow
// a gross pot reading.
TEST(NoiseAdaptation, GrossReadingsUnderARobustLossLeaveSigmaNearTheTruth) {
  const RobotModel robot = RobotModel::fromString(test::kArmUrdf, "arm4");
  const SensorsFile truth = parseSensorsYaml(test::kArmTruth, "arm4_truth", robot);
  const MeasurementModel model(robot, truth.sensors);
  SimulationOptions so;
  so.frames = 400;
  so.outliers = 0.05;
  so.seed = 4;
  const Simulation sim = simulate(model, truth.theta, so);
  const Observations obs = bindLog(sim.data.log, truth.sensors, "truth", 1.0);
  CalibrationOptions o;
  o.threads = 2;
  o.loss = LossKind::kHuber;
  const CalibrationResult r = calibrate(robot, truth.sensors, truth.theta, obs, o);
  const double limit[kNumSensorGroups] = {1.3, 2.5, 1.6};
  for (int g = 0; g < kNumSensorGroups; ++g) {
    const double ratio = r.summary.group_sigma[g] / r.summary.seed_group_sigma[g];
    EXPECT_GT(ratio, 0.8) << groupName(static_cast<SensorGroup>(g));
    EXPECT_LT(ratio, limit[g]) << groupName(static_cast<SensorGroup>(g));
  }
  EXPECT_FALSE(r.summary.suspect()) << r.summary.verdict[0];
}

}  // namespace
}  // namespace stac
