// A run that never converges never reaches the escapes (alternation.cpp),
// which are tried from converged runs only: the bundled hand on partial
// swings, basin truth 7, descended into a wrong minimum of its thumb (the
// IP pot's gain +0.82 where the truth's is -0.54, the MCP pot's 0.29 for
// 0.66, the thumb's markers at 3x their σ) and crawled there, the cost
// falling by 2e-5 of itself an iteration, until the limit of 200:
// "not converged", flagged, the truth never tried. A run unconverged after
// kStallCheck iterations with a sensor misfit is paused and the escapes
// tried from there; this one must now reach the truth with verdict ok.
#include <gtest/gtest.h>

#include <string>

#include "stac/calibrate.hpp"
#include "support/basin_draws.hpp"

namespace stac {
namespace {

TEST(StalledRun, AHandStalledInAWrongThumbMinimumIsEscapedFrom) {
  const test::Robot robot = test::bundledRobot("hand24", 500);
  const auto [truth, r] = test::replayBasinTruth(robot, test::Variant::kPartialSwings, 7);
  std::string why;
  EXPECT_TRUE(test::closeToTruth(robot.truth.sensors, truth, r, &why)) << why;
  EXPECT_TRUE(r.summary.converged);
  EXPECT_FALSE(r.summary.suspect()) << r.summary.verdict[0];
}

}  // namespace
}  // namespace stac
