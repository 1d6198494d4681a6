// The verdict under a robust loss (methods/verdict.cpp checkMedians): a
// redescending loss ignores whatever readings a fit leaves far off, so a
// wrong minimum that fits most frames of a sensor and leaves the rest
// ignored keeps its median within bounds. The error below which 80% of a
// sensor's readings lie (MedianError::upper) tells: a sensor with a fifth
// or more of its readings far off is named, and the 5% of gross readings
// that every sensor of the arm has are no reason.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

#include "solve/statistics.hpp"
#include "stac/calibrate.hpp"
#include "support/arm_fixture.hpp"

namespace stac {
namespace {

// Moves `share` of pot j's readings by one offset of 40-60 σ: a stretch of
// frames from a third of the log on, which no neighbour in time gives away
// as spikes. Pot 0 (the first joint, which every marker sees, so that the
// frames' angles cannot follow the offset).
void moveStretchOfPot(const test::ArmProblem& p, int j, double share, Observations* obs) {
  const double sigma = p.sensors.joint_sensors[j].sigma;
  const int n = obs->num_frames;
  const int length = static_cast<int>(share * n);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(40, 60);
  const double offset = u(rng) * sigma;
  for (int t = n / 3; t < n / 3 + length; ++t)
    if (!std::isnan(obs->joint(t, j))) obs->joint(t, j) += offset;
}

CalibrationResult cauchyFit(const test::ArmProblem& p, const Observations& obs) {
  CalibrationOptions o;
  o.threads = 2;
  o.loss = LossKind::kCauchy;
  return calibrate(p.robot, p.sensors, p.seed, obs, o);
}

bool names(const CalibrationResult& r, const std::string& sensor) {
  for (const std::string& reason : r.summary.verdict)
    if (reason.find("sensor " + sensor + ": 20% or more of its readings are off") !=
        std::string::npos)
      return true;
  return false;
}

TEST(RobustVerdict, UpperErrorIsTheQuantileBelowWhichFourFifthsLie) {
  test::ArmProblem p = test::makeArmProblem(200, 5, 0.0);  // noise-free
  const MeasurementModel model(p.robot, p.sensors);
  // 30% of pot 1's readings off by exactly 0.5, the rest exact.
  for (int t = 0; t < 60; ++t) p.obs.joint(t, 1) += 0.5;
  const auto errors = medianErrors(model, p.truth, p.obs, p.q_true, 1);
  EXPECT_NEAR(errors[1][1].median, 0.0, 1e-9);
  EXPECT_NEAR(errors[1][1].upper, 0.5, 1e-9);
  EXPECT_NEAR(errors[1][0].upper, 0.0, 1e-9);
}

TEST(RobustVerdict, ASensorWithAFifthOfItsReadingsFarOffIsNamed) {
  test::ArmProblem p = test::makeArmProblem(300, 5);
  Observations obs = p.obs;
  moveStretchOfPot(p, 0, 0.3, &obs);
  const CalibrationResult r = cauchyFit(p, obs);
  ASSERT_TRUE(r.summary.suspect());
  EXPECT_TRUE(names(r, p.sensors.joint_sensors[0].name)) << r.summary.verdict[0];
}

TEST(RobustVerdict, FivePercentOfGrossReadingsAreNoReason) {
  test::ArmProblem p = test::makeArmProblem(300, 5);
  test::addOutliers(p.sensors, 0.05, 9, &p.obs);
  const CalibrationResult r = cauchyFit(p, p.obs);
  EXPECT_FALSE(r.summary.suspect()) << r.summary.verdict[0];
  // The same sensor's fifth then is.
  Observations obs = p.obs;
  moveStretchOfPot(p, 0, 0.3, &obs);
  EXPECT_TRUE(names(cauchyFit(p, obs), p.sensors.joint_sensors[0].name));
}

}  // namespace
}  // namespace stac
