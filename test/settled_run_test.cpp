// A run the iteration limit stops is converged when its last steps shrink
// geometrically to a tail below a tenth of every determined parameter's std
// (settled_run.hpp): the bundled hand on partial swings (basin truth 13 of
// the second noise draw) crawled for 200 iterations along its thumb's
// undetermined trade-off, the cost rising by 1e-7 of itself an iteration as
// σ followed, every determined parameter moving by 0.001 std an iteration:
// "not converged", a right calibration flagged (a false alarm).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "methods/settled_run.hpp"
#include "stac/sensors_file.hpp"
#include "support/arm_files.hpp"
#include "support/basin_draws.hpp"

namespace stac {
namespace {

struct Trail {
  RobotModel robot = RobotModel::fromString(test::kArmUrdf, "arm4");
  SensorsFile file = parseSensorsYaml(test::kArmTruth, "arm4_truth", robot);
  ThetaSpace space{file.sensors};
  Eigen::VectorXd std = Eigen::VectorXd::Constant(space.size(), 0.01);

  // Four iterates approaching the truth geometrically: step k (1-3) moves
  // every free entry by first·ρ^(k-1) of its std; σ's scales by scale_step
  // each (not shrinking unless 0).
  IterationTrail approach(double first, double rho, double scale_step = 0.0,
                          int moving_entry = -1, double moving_step = 0.0) const {
    IterationTrail trail;
    Eigen::VectorXd at = Eigen::VectorXd::Zero(space.size());
    GroupScales scales;
    for (int k = 0; k < kTrailLength; ++k) {
      trail.push(space.plus(file.theta, at), scales);
      for (int i : space.freeIndex()) at[i] += first * std::pow(rho, k) * std[i];
      if (moving_entry >= 0) at[moving_entry] += moving_step;
      for (double& kappa : scales.kappa) kappa += scale_step;
    }
    return trail;
  }
};

TEST(SettledRun, StepsShrinkingToATailBelowATenthOfTheStdHaveSettled) {
  const Trail t;
  // Last step 0.01·0.8² std, tail ρ/(1-ρ) = 4 of it: 0.026 std left.
  EXPECT_TRUE(settledWithinStd(t.space, t.approach(0.01, 0.8), t.std));
  // The same last step at a rate of 0.99: 0.97 std left.
  EXPECT_FALSE(settledWithinStd(t.space, t.approach(0.0102, 0.99), t.std));
  // Steps that do not shrink never settle.
  EXPECT_FALSE(settledWithinStd(t.space, t.approach(1e-4, 1.0), t.std));
  EXPECT_FALSE(settledWithinStd(t.space, t.approach(1e-4, 1.2), t.std));
  // Nothing moving has settled.
  EXPECT_TRUE(settledWithinStd(t.space, t.approach(0.0, 0.5), t.std));
}

TEST(SettledRun, AnUndeterminedParameterMayStillMove) {
  Trail t;
  const int i = t.space.freeIndex()[3];
  const IterationTrail trail = t.approach(0.01, 0.8, 0.0, i, 0.5);
  EXPECT_FALSE(settledWithinStd(t.space, trail, t.std));  // 50 std a step
  t.std[i] = INFINITY;  // reported undetermined: no std to settle within
  EXPECT_TRUE(settledWithinStd(t.space, trail, t.std));
}

TEST(SettledRun, SigmaStillMovingHasNotSettled) {
  const Trail t;
  EXPECT_FALSE(settledWithinStd(t.space, t.approach(0.01, 0.8, 1e-3), t.std));
}

TEST(SettledRun, AShortTrailHasNotSettled) {
  const Trail t;
  IterationTrail trail = t.approach(0.0, 0.5);
  trail.theta.erase(trail.theta.begin());
  trail.scales.erase(trail.scales.begin());
  EXPECT_FALSE(settledWithinStd(t.space, trail, t.std));
}

TEST(SettledRun, AHandCrawlingAlongItsThumbsTradeOffAtTheLimitIsConverged) {
  const test::Robot robot = test::bundledRobot("hand24", 500);
  CalibrationOptions o;
  o.threads = 2;
  const auto [truth, r] =
      test::replayBasinTruth(robot, test::Variant::kPartialSwings, 13, LossKind::kHuber, o, 2);
  std::string why;
  EXPECT_TRUE(test::withinReportedStd(robot.truth.sensors, truth, r, &why)) << why;
  EXPECT_EQ(r.summary.iterations, o.max_iterations);  // the limit stopped it
  EXPECT_TRUE(r.summary.converged);
  EXPECT_FALSE(r.summary.suspect()) << r.summary.verdict[0];
  EXPECT_FALSE(r.summary.unidentifiable.empty());  // the thumb's trade-off
}

}  // namespace
}  // namespace stac
