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

}  // namespace
}  // namespace stac
