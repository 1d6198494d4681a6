// A converged run whose sensors still misfit after every jump is restarted
// from the initialisation's tree-order start (alternation.cpp
// restartInTreeOrder). An unseen planar double pendulum (continuous
// joints, example-robot-data) on partial swings, the basin test's truth 4:
// the sweeps' start ended in a mirror image of the motion, the markers at
// 2.7x their seed σ (one at 3.9x), both pots' signs flipped, no jump
// better, verdict ok.
#include <gtest/gtest.h>

#include <random>
#include <string>

#include "stac/calibrate.hpp"
#include "support/basin_draws.hpp"

namespace stac {
namespace {

TEST(TreeRestart, AMirroredDoublePendulumIsRestartedInTreeOrder) {
  const test::Robot pendulum = test::externalRobot(
      RobotModel::fromFile(std::string(STAC_SOURCE_DIR) +
                           "/test/fixtures/double_pendulum_continuous_kinematics.urdf"),
      600);
  const SensorSet& sensors = pendulum.truth.sensors;
  const auto [truth, r] = test::replayBasinTruth(pendulum, test::Variant::kPartialSwings, 4);
  std::string why;
  EXPECT_TRUE(test::closeToTruth(sensors, truth, r, &why)) << why;
  EXPECT_FALSE(r.summary.suspect()) << r.summary.verdict[0];
  for (size_t j = 0; j < sensors.joint_sensors.size(); ++j)
    EXPECT_GT(r.theta.joint_sensor[j].gain * truth.joint_sensor[j].gain, 0) << j;
}

}  // namespace
}  // namespace stac
