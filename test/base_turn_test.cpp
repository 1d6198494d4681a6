// A base whose only marker sits far from the limb's root (test/fixtures
// falcon_bravo7_kinematics.urdf: a Bravo 7 arm on a Falcon ROV, the ROV's
// one marker 0.73 m from the arm's first joint): the first stages of the
// tree-order search see that marker and the first links' only, which leave
// the world's half turn about the line through them open, so the search
// also starts from the seed's mocap frame turned so (tree_search.cpp
// seedFrames). Without it, basin truths 6 and 7 of the default draw on
// partial swings ended with the first joints mirrored and the mocap frame
// ~π off, flagged (markers at 3.7x their σ; joint readings at 12x).
#include <gtest/gtest.h>

#include <string>

#include "stac/calibrate.hpp"
#include "support/basin_draws.hpp"

namespace stac {
namespace {

test::Robot falcon() {
  return test::externalRobot(
      RobotModel::fromFile(std::string(STAC_SOURCE_DIR) +
                           "/test/fixtures/falcon_bravo7_kinematics.urdf"),
      600);
}

void expectReached(int index) {
  const test::Robot robot = falcon();
  auto [truth, r] = test::replayBasinTruth(robot, test::Variant::kPartialSwings, index,
                                           LossKind::kHuber, CalibrationOptions(), 0, 2024);
  std::string why;
  EXPECT_TRUE(test::closeToTruth(robot.truth.sensors, truth, r, &why)) << index << ": " << why;
  EXPECT_TRUE(r.summary.converged) << index;
  EXPECT_FALSE(r.summary.suspect()) << index << ": " << r.summary.verdict[0];
}

TEST(BaseTurn, AnArmFarFromItsBasesOnlyMarkerIsNotLeftTurnedWithTheWorld) { expectReached(6); }

TEST(BaseTurn, AnArmFarFromItsBasesOnlyMarkerIsNotLeftTurnedWithTheWorldToo) {
  expectReached(7);
}

}  // namespace
}  // namespace stac
