// Where the base's markers leave the world's half turn open (one base
// marker, the arm rooted on the line through it), a run can converge with
// the world turned and the arm mirrored with it: a minimum no jump reaches
// (jumps move joints, not the world) that fits only a little worse, its
// markers at 1.6-1.9x their seed σ. There the tree-order restart is tried
// from the jumps' own mark, 1.4x (alternation.cpp treeRestartMisfit), not
// 2x. A two-joint flying arm (test/fixtures/two_joint_flying_arm_kinematics.urdf,
// the Borinot's joint placements), partial swings, the basin's fresh truth
// draw 13, truth 1: before, the mocap frame 3.0 rad off the truth, both
// pots' signs flipped, verdict ok.
#include <gtest/gtest.h>

#include <string>

#include "stac/calibrate.hpp"
#include "support/basin_draws.hpp"

namespace stac {
namespace {

TEST(WorldTurnRestart, AnArmMirroredWithTheWorldTurnedIsRestartedInTreeOrder) {
  const test::Robot arm = test::externalRobot(
      RobotModel::fromFile(std::string(STAC_SOURCE_DIR) +
                           "/test/fixtures/two_joint_flying_arm_kinematics.urdf"),
      600);
  const SensorSet& sensors = arm.truth.sensors;
  const auto [truth, r] = test::replayBasinTruth(arm, test::Variant::kPartialSwings, 1,
                                                 LossKind::kHuber, CalibrationOptions(), 0, 13);
  std::string why;
  EXPECT_TRUE(test::closeToTruth(sensors, truth, r, &why)) << why;
  EXPECT_FALSE(r.summary.suspect()) << r.summary.verdict[0];
  for (size_t j = 0; j < sensors.joint_sensors.size(); ++j)
    EXPECT_GT(r.theta.joint_sensor[j].gain * truth.joint_sensor[j].gain, 0) << j;
}

}  // namespace
}  // namespace stac
