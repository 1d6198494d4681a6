// Chain flips (minimumMoves): a joint half a turn, the joints below it
// mirrored (the first about zero or over the top, π − q), closed by a half
// turn below them or by the chain's end. Two unseen robots on partial
// swings converged in such mirrors, flagged (a joint beyond its URDF limit
// in most frames), and no jump the escape tried reached the truth:
//  - Finger Edu, basin truth 0: its roll and two flexions over the top
//    (q1 + π, π − q2, −q3), the roll beyond its limit in 582 of 600 frames;
//  - Unitree Z1, basin truth 2: its base yaw, three pitches and wrist over
//    the top, closed by its last roll (q1 + π, π − q2, −q3..−q5, q6 + π),
//    at exactly the truth's cost, after a tree-order restart whose end the
//    jumps were not tried from; joint 1 beyond its limit in 341 of 600.
// Both replayed (test/fixtures) must reach the truth with verdict ok.
#include <gtest/gtest.h>

#include <string>

#include "stac/calibrate.hpp"
#include "support/basin_draws.hpp"

namespace stac {
namespace {

void expectPartialTruthReached(const std::string& fixture, int index) {
  const test::Robot robot = test::externalRobot(
      RobotModel::fromFile(std::string(STAC_SOURCE_DIR) + "/test/fixtures/" + fixture), 600);
  const auto [truth, r] = test::replayBasinTruth(robot, test::Variant::kPartialSwings, index);
  std::string why;
  EXPECT_TRUE(test::closeToTruth(robot.truth.sensors, truth, r, &why)) << why;
  EXPECT_FALSE(r.summary.suspect()) << r.summary.verdict[0];
}

TEST(ChainFlips, AFingersRollOverTheTopIsFoundBack) {
  expectPartialTruthReached("finger_edu_kinematics.urdf", 0);
}

TEST(ChainFlips, AnArmsMirrorClosedByItsLastRollIsFoundBackAfterARestart) {
  expectPartialTruthReached("z1_kinematics.urdf", 2);
}

}  // namespace
}  // namespace stac
