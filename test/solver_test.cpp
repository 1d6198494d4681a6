// STAC on a small arm with known truth.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>

#include "stac/calibrate.hpp"
#include "solve/pass.hpp"
#include "solve/problem.hpp"
#include "support/arm_fixture.hpp"

namespace stac {
namespace {

// Every identifiable parameter within k reported standard deviations.
void expectWithinStd(const test::ArmProblem& p, const CalibrationResult& r, double k) {
  const SensorParameters& th = r.theta;
  for (size_t j = 0; j < p.sensors.joint_sensors.size(); ++j) {
    const GainBias& sd = r.std.joint_sensor[j];
    if (std::isfinite(sd.gain)) {
      EXPECT_LT(std::abs(th.joint_sensor[j].gain - p.truth.joint_sensor[j].gain), k * sd.gain + 1e-12)
          << p.sensors.joint_sensors[j].name;
    }
    if (std::isfinite(sd.bias)) {
      EXPECT_LT(std::abs(th.joint_sensor[j].bias - p.truth.joint_sensor[j].bias), k * sd.bias + 1e-12)
          << p.sensors.joint_sensors[j].name;
    }
  }
  for (size_t j = 0; j < p.sensors.tendon_sensors.size(); ++j) {
    EXPECT_LT(std::abs(th.tendon_sensor[j].gain - p.truth.tendon_sensor[j].gain),
              k * r.std.tendon_sensor[j].gain + 1e-12);
    EXPECT_LT(std::abs(th.tendon_sensor[j].bias - p.truth.tendon_sensor[j].bias),
              k * r.std.tendon_sensor[j].bias + 1e-12);
  }
  for (size_t m = 0; m < p.sensors.markers.size(); ++m)
    for (int i = 0; i < 3; ++i)
      if (std::isfinite(r.std.marker_position[m][i])) {
        EXPECT_LT(std::abs(th.marker_position[m][i] - p.truth.marker_position[m][i]),
                  k * r.std.marker_position[m][i] + 1e-12)
            << p.sensors.markers[m].name;
      }
  for (int i = 0; i < 3; ++i)
    EXPECT_LT(std::abs(th.mocap.translation[i] - p.truth.mocap.translation[i]),
              k * r.std.mocap_translation[i] + 1e-12);
  const Eigen::AngleAxisd err(th.mocap.rotation * p.truth.mocap.rotation.inverse());
  EXPECT_LT(err.angle(), k * r.std.mocap_rotation.norm() + 1e-12);
}

TEST(Stac, ArmFromPaperSeedingRecoversTruth) {
  test::ArmProblem p = test::makeArmProblem(500, 11);
  CalibrationOptions o;
  o.threads = 2;
  if (std::getenv("STAC_DEBUG"))
    o.progress = [](const IterationReport& r) {
      std::fprintf(stderr, "%s %d cost %.6g rms %.4g %.4g %.4g\n", r.stage.c_str(), r.iteration,
                   r.cost, r.rms[0], r.rms[1], r.rms[2]);
    };
  CalibrationResult r = calibrate(p.robot, p.sensors, p.seed, p.obs, o);
  EXPECT_TRUE(r.summary.converged) << r.summary.iterations;
  EXPECT_TRUE(r.summary.unidentifiable.empty())
      << r.summary.unidentifiable.front().reason;
  expectWithinStd(p, r, 4.0);
  // Adapted σ close to the injected noise.
  EXPECT_NEAR(r.summary.group_sigma[0], 0.002, 0.0004);
  EXPECT_NEAR(r.summary.group_sigma[1], 0.01, 0.002);
}

}  // namespace
}  // namespace stac

namespace stac {
namespace {

CalibrationOptions quietOptions() {
  CalibrationOptions o;
  o.threads = 2;
  return o;
}

TEST(Stac, EveryQPhaseVariantConverges) {
  test::ArmProblem p = test::makeArmProblem(300, 5);
  for (QPhaseMethod m : {QPhaseMethod::kLmIter, QPhaseMethod::kLmBatch, QPhaseMethod::kBfgs}) {
    CalibrationOptions o = quietOptions();
    o.stac.q_phase = m;
    CalibrationResult r = calibrate(p.robot, p.sensors, p.seed, p.obs, o);
    EXPECT_TRUE(r.summary.converged) << static_cast<int>(m);
    expectWithinStd(p, r, 4.0);
  }
}

TEST(Stac, ThirtyPercentMarkerDropout) {
  test::ArmProblem p = test::makeArmProblem(600, 21, 1.0, 0.3);
  CalibrationResult r = calibrate(p.robot, p.sensors, p.seed, p.obs, quietOptions());
  EXPECT_TRUE(r.summary.converged);
  expectWithinStd(p, r, 4.0);
}

TEST(Stac, FreeBaseMarkerIsReportedUnidentifiable) {
  test::ArmProblem p = test::makeArmProblem(300, 8);
  p.sensors.markers[0].fixed = false;  // m_base: now its position trades off
  p.seed.marker_position[0].setZero();
  CalibrationResult r = calibrate(p.robot, p.sensors, p.seed, p.obs, quietOptions());
  ASSERT_FALSE(r.summary.unidentifiable.empty());
  bool found = false;
  for (const UnidentifiableDirection& d : r.summary.unidentifiable) {
    const bool has_bias = std::find(d.parameters.begin(), d.parameters.end(),
                                    "joint_sensors.j1_pot.bias") != d.parameters.end();
    // A gauge: exactly null, so it excuses j1 from the verdict's limit check.
    found |= has_bias && d.reason.find("j1 axis") != std::string::npos &&
             d.kind == Undetermined::kNull;
  }
  EXPECT_TRUE(found) << r.summary.unidentifiable.front().reason;
  EXPECT_FALSE(std::isfinite(r.std.joint_sensor[0].bias));
  // The fit itself is still right: the noise estimates match the injected.
  EXPECT_NEAR(r.summary.group_sigma[0], 0.002, 0.0004);
  EXPECT_NEAR(r.summary.group_sigma[1], 0.01, 0.002);
}

// Over kInitFrames frames the log is solved on a subsample first and the
// coupled steps take their curvature from a sample of frames: both paths.
class ShortAndLongLogs : public ::testing::TestWithParam<int> {};
INSTANTIATE_TEST_SUITE_P(Stac, ShortAndLongLogs, ::testing::Values(300, 2500));

TEST_P(ShortAndLongLogs, IdenticalResultsWithOneAndTwoThreads) {
  test::ArmProblem p = test::makeArmProblem(GetParam(), 9);
  CalibrationOptions o1 = quietOptions(), o2 = quietOptions();
  o1.threads = 1;
  RowMatrix q1, q2;
  CalibrationResult r1 = calibrate(p.robot, p.sensors, p.seed, p.obs, o1, &q1);
  CalibrationResult r2 = calibrate(p.robot, p.sensors, p.seed, p.obs, o2, &q2);
  EXPECT_EQ(r1.summary.iterations, r2.summary.iterations);
  EXPECT_TRUE((q1.array() == q2.array()).all());
  for (size_t j = 0; j < r1.theta.joint_sensor.size(); ++j) {
    EXPECT_EQ(r1.theta.joint_sensor[j].gain, r2.theta.joint_sensor[j].gain);
    EXPECT_EQ(r1.theta.joint_sensor[j].bias, r2.theta.joint_sensor[j].bias);
  }
  for (size_t m = 0; m < r1.theta.marker_position.size(); ++m)
    EXPECT_TRUE(r1.theta.marker_position[m] == r2.theta.marker_position[m]);
  EXPECT_EQ(r1.summary.final_cost, r2.summary.final_cost);
}

}  // namespace
}  // namespace stac

namespace stac {
namespace {

TEST_P(ShortAndLongLogs, MonolithicAndAlternationReachTheSameCost) {
  test::ArmProblem p = test::makeArmProblem(GetParam() == 300 ? 200 : GetParam(), 3);
  CalibrationOptions o;
  o.threads = 2;
  o.adapt_variance = false;  // same fixed σ: the two costs are comparable
  o.tolerance = 1e-12;
  CalibrationResult stac = calibrate(p.robot, p.sensors, p.seed, p.obs, o);
  o.method = Method::kMonolithic;
  o.max_iterations = 500;
  CalibrationResult joint = calibrate(p.robot, p.sensors, p.seed, p.obs, o);
  EXPECT_TRUE(stac.summary.converged);
  EXPECT_TRUE(joint.summary.converged);
  EXPECT_LT(std::abs(stac.summary.final_cost - joint.summary.final_cost) /
                joint.summary.final_cost, 1e-6)
      << stac.summary.final_cost << " vs " << joint.summary.final_cost;
  expectWithinStd(p, joint, 4.0);
}

}  // namespace
}  // namespace stac

namespace stac {
namespace {

TEST(Stac, HuberLossSurvivesFivePercentOutliersAndListsThem) {
  test::ArmProblem p = test::makeArmProblem(500, 12);
  const auto outliers = test::addOutliers(p.sensors, 0.05, 99, &p.obs);
  ASSERT_GT(outliers.size(), 50u);
  CalibrationOptions o;
  o.threads = 2;
  o.loss = LossKind::kHuber;
  o.max_downweighted = 20;
  o.screen_spikes = false;  // the loss's own work (the screen: spike_screen_test)
  CalibrationResult r = calibrate(p.robot, p.sensors, p.seed, p.obs, o);
  EXPECT_TRUE(r.summary.converged);
  expectWithinStd(p, r, 4.0);
  ASSERT_EQ(r.summary.downweighted.size(), 20u);
  int found = 0;
  for (const DownweightedReading& d : r.summary.downweighted)
    for (const auto& [t, name] : outliers) found += (t == d.frame && name == d.sensor);
  EXPECT_EQ(found, 20);  // every listed reading is an injected outlier
}

// What the Huber run sets aside once converged (pass.hpp
// withoutGrossReadings): at the truth, exactly the injected gross readings
// (20-60 σ, 5-20 cm), each as a whole (a marker's three coordinates), and
// nothing else: the clean readings' 5.2 σ bound is passed once in 4 million.
TEST(Stac, GrossReadingsSetAsideAreExactlyTheInjectedOnes) {
  test::ArmProblem p = test::makeArmProblem(500, 12);
  const Observations clean = p.obs;
  const auto outliers = test::addOutliers(p.sensors, 0.05, 99, &p.obs);
  const MeasurementModel model(p.robot, p.sensors);
  const NoiseModel noise = NoiseModel::fromSeeds(p.sensors);
  const RobustLoss huber(LossKind::kHuber, 3.0);
  const Problem problem{model, p.obs, noise, huber, 2};
  int count = -1;
  const Observations kept = withoutGrossReadings(problem, p.truth, noise, p.q_true, &count);
  EXPECT_EQ(count, static_cast<int>(outliers.size()));
  const SensorSet& s = p.sensors;
  auto setAside = [&](int t, const std::string& name) {
    for (size_t m = 0; m < s.markers.size(); ++m)
      if (s.markers[m].name == name)
        return kept.marker.block(t, 3 * m, 1, 3).array().isNaN().all() &&
               !std::isnan(clean.marker(t, 3 * m));
    for (size_t j = 0; j < s.joint_sensors.size(); ++j)
      if (s.joint_sensors[j].name == name) return std::isnan(kept.joint(t, j));
    for (size_t j = 0; j < s.tendon_sensors.size(); ++j)
      if (s.tendon_sensors[j].name == name) return std::isnan(kept.tendon(t, j));
    return false;
  };
  for (const auto& [t, name] : outliers) EXPECT_TRUE(setAside(t, name)) << t << " " << name;
  // Nothing else: as many readings missing as the clean log's plus those.
  auto missing = [](const Observations& o) {
    return o.marker.array().isNaN().count() / 3 + o.joint.array().isNaN().count() +
           o.tendon.array().isNaN().count();
  };
  EXPECT_EQ(missing(kept), missing(clean) + static_cast<long>(outliers.size()));
}

TEST(Stac, ReportedStdMatchesTheSpreadOverNoiseSeeds) {
  const int kSeeds = 12;
  std::vector<CalibrationResult> results;
  test::ArmProblem p0 = test::makeArmProblem(300, 4, 1.0, 0.0, 0);
  for (int s = 0; s < kSeeds; ++s) {
    test::ArmProblem p = test::makeArmProblem(300, 4, 1.0, 0.0, 100 + s);
    CalibrationOptions o;
    o.threads = 2;
    results.push_back(calibrate(p.robot, p.sensors, p.seed, p.obs, o));
  }
  // Per joint sensor gain/bias and per marker coordinate: the empirical
  // spread against the mean reported std.
  auto check = [&](auto value, auto reported, const std::string& what) {
    double mean = 0, var = 0, std_mean = 0;
    for (const auto& r : results) mean += value(r) / kSeeds;
    for (const auto& r : results) {
      var += (value(r) - mean) * (value(r) - mean) / (kSeeds - 1);
      std_mean += reported(r) / kSeeds;
    }
    const double spread = std::sqrt(var);
    EXPECT_GT(std_mean, spread / 2) << what;
    EXPECT_LT(std_mean, spread * 2) << what;
  };
  for (size_t j = 0; j < p0.sensors.joint_sensors.size(); ++j) {
    check([j](const CalibrationResult& r) { return r.theta.joint_sensor[j].gain; },
          [j](const CalibrationResult& r) { return r.std.joint_sensor[j].gain; },
          p0.sensors.joint_sensors[j].name + ".gain");
    check([j](const CalibrationResult& r) { return r.theta.joint_sensor[j].bias; },
          [j](const CalibrationResult& r) { return r.std.joint_sensor[j].bias; },
          p0.sensors.joint_sensors[j].name + ".bias");
  }
  for (size_t m = 0; m < p0.sensors.markers.size(); ++m) {
    if (p0.sensors.markers[m].fixed) continue;
    for (int i = 0; i < 3; ++i)
      check([m, i](const CalibrationResult& r) { return r.theta.marker_position[m][i]; },
            [m, i](const CalibrationResult& r) { return r.std.marker_position[m][i]; },
            p0.sensors.markers[m].name);
  }
}

// Readings of one frame sharing an error (virtual points of one tracked
// body; a mocap frame jittering as a whole) carry less information than
// independent ones: the sandwich std (uncertainty.hpp) follows the real
// spread of the estimate where the noise model's own std would claim more.
TEST(Stac, StdFollowsTheSpreadWhenAFramesMarkersShareAnError) {
  const int kSeeds = 16;
  std::vector<double> tx, sd;
  for (int seed = 0; seed < kSeeds; ++seed) {
    test::ArmProblem p = test::makeArmProblem(300, 4, 1.0, 0.0, 200 + seed);
    const double shared = 4.0 * p.sensors.markers[0].sigma;
    std::mt19937 rng(300 + seed);
    std::normal_distribution<double> n(0.0, shared);
    for (int t = 0; t < p.obs.num_frames; ++t) {
      const Eigen::Vector3d c(n(rng), n(rng), n(rng));
      for (Eigen::Index m = 0; m < p.obs.marker.cols() / 3; ++m)
        for (int i = 0; i < 3; ++i) p.obs.marker(t, 3 * m + i) += c[i];
    }
    // The seed σ states the readings' total spread, as a user who measured
    // it would: the fit is then sound (a misfit would only add the escape
    // search, seconds per seed) and only the std's model is on trial.
    for (MarkerConfig& m : p.sensors.markers) m.sigma = std::hypot(m.sigma, shared);
    CalibrationOptions o;
    o.threads = 2;
    CalibrationResult r = calibrate(p.robot, p.sensors, p.seed, p.obs, o);
    // Stated right, errors shared within a frame are no reason for alarm.
    EXPECT_TRUE(r.summary.verdict.empty()) << "seed " << seed;
    for (int i = 0; i < 3; ++i) {
      tx.push_back(r.theta.mocap.translation[i] - p.truth.mocap.translation[i]);
      sd.push_back(r.std.mocap_translation[i]);
    }
  }
  double ms = 0, mean_sd = 0;
  for (size_t k = 0; k < tx.size(); ++k) ms += tx[k] * tx[k] / tx.size(), mean_sd += sd[k] / sd.size();
  const double spread = std::sqrt(ms);
  EXPECT_GT(mean_sd, 0.8 * spread);
  EXPECT_LT(mean_sd, 1.5 * spread);
}

// A log far longer than the initialisation's subsample (kInitFrames = 1000,
// here 100 frames apart): every frame starts from q_t solved on ever denser
// frames, never interpolated across a wide gap, so the start already fits
// at the noise and a few iterations finish (a 250,000-frame humanoid took
// 13 iterations from a start at twice its noise; 5 now).
TEST(Stac, VeryLongLogStartsAtTheNoise) {
  test::ArmProblem p = test::makeArmProblem(100000, 6);
  CalibrationOptions o;
  o.threads = 2;
  double init_rms[kNumSensorGroups] = {-1, -1, -1};
  o.progress = [&](const IterationReport& r) {
    if (r.stage == "init") std::copy(r.rms, r.rms + kNumSensorGroups, init_rms);
  };
  CalibrationResult r = calibrate(p.robot, p.sensors, p.seed, p.obs, o);
  EXPECT_TRUE(r.summary.converged);
  EXPECT_LE(r.summary.iterations, 8);
  for (int g = 0; g < kNumSensorGroups; ++g) {
    if (!r.summary.group_present[g]) continue;
    EXPECT_GT(init_rms[g], 0) << "group " << g;
    EXPECT_LT(init_rms[g], 1.1 * r.summary.after_rms[g]) << "group " << g;
  }
  EXPECT_TRUE(r.summary.verdict.empty());
  expectWithinStd(p, r, 4.0);
}

}  // namespace
}  // namespace stac
