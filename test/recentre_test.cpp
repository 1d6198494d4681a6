// A joint whose absolute angle only a marker on its own last link sees can
// end with its whole motion beyond a limit at the truth's cost: a constant
// shift of the angle is taken up by that marker's position. The bundled
// hand on partial swings (basin truth 4 of noise draw 2) converged so, its
// ring finger's last joint 1.4 rad off, beyond its limit in 498 of 500
// frames, flagged, and no discrete jump (sign, half or whole turn) brought
// it back. The escape's recentring move (recentreMoves) shifts the motion
// into the limits; the run must now reach the truth with verdict ok.
#include <gtest/gtest.h>

#include <string>

#include "stac/calibrate.hpp"
#include "support/basin_draws.hpp"

namespace stac {
namespace {

TEST(Recentre, AFingerTipsMotionBeyondItsLimitIsShiftedBackIntoThem) {
  const test::Robot robot = test::bundledRobot("hand24", 500);
  const auto [truth, r] = test::replayBasinTruth(robot, test::Variant::kPartialSwings, 4,
                                                 LossKind::kHuber, CalibrationOptions(), 2);
  std::string why;
  EXPECT_TRUE(test::closeToTruth(robot.truth.sensors, truth, r, &why)) << why;
  EXPECT_FALSE(r.summary.suspect()) << r.summary.verdict[0];
}

// Not only a motion beyond its limits in most frames: an unseen Unitree B1
// on partial swings (the basin's fresh truth draw 13, truth 3), whose
// rear-left calf's marker lies near the knee's axis, converged with the
// calf's motion mirrored at half scale, below the knee's lower limit in
// 169 of 600 frames (by more than 3 std of each frame's angle), the calf
// pot's gain and bias listed as weakly determined and the thigh's marker
// 1.4 mm (10 std) off: verdict ok (the listing excused the knee from the
// limit check), then flagged. The placements are now tried wherever the
// verdict would flag the motion (kSuspectShareAtLimit of the frames), and
// one of them reaches the truth.
TEST(Recentre, ACalfMirroredAtHalfScaleBelowItsLimitIsPlacedBack) {
  const test::Robot robot = test::externalRobot(
      RobotModel::fromFile(std::string(STAC_SOURCE_DIR) + "/test/fixtures/b1_kinematics.urdf"),
      600);
  const auto [truth, r] = test::replayBasinTruth(robot, test::Variant::kPartialSwings, 3,
                                                 LossKind::kHuber, CalibrationOptions(), 0, 13);
  std::string why;
  EXPECT_TRUE(test::closeToTruth(robot.truth.sensors, truth, r, &why)) << why;
  EXPECT_FALSE(r.summary.suspect()) << r.summary.verdict[0];
}

}  // namespace
}  // namespace stac
