// A run that crawls in a wrong minimum and converges there only because it
// was given the iterations (a user told "not converged, raise
// --max-iterations" would do just that) must not pass as ok: the bundled
// hand on partial swings, basin truth 10, with a limit of 1500 converged
// after 768 iterations with two thumb pots' signs flipped, its thumb's
// sensors at 1.4-2.7x their σ, under the verdict's per-sensor bound, and
// passed as ok (alternation.cpp slowConvergence). Long: the run takes
// minutes.
#include <gtest/gtest.h>

#include <string>

#include "stac/calibrate.hpp"
#include "support/basin_draws.hpp"

namespace stac {
namespace {

TEST(SlowConvergence, ACrawlThatConvergesInAWrongMinimumIsSuspect) {
  const test::Robot robot = test::bundledRobot("hand24", 500);
  CalibrationOptions o;
  o.max_iterations = 1500;
  const auto [truth, r] =
      test::replayBasinTruth(robot, test::Variant::kPartialSwings, 10, LossKind::kHuber, o);
  std::string why;
  if (test::closeToTruth(robot.truth.sensors, truth, r, &why)) {
    EXPECT_FALSE(r.summary.suspect()) << r.summary.verdict[0];  // reached: no false alarm
    return;
  }
  ASSERT_TRUE(r.summary.suspect()) << "a wrong minimum (" << why << ") passed as ok";
  if (!r.summary.converged) return;  // "not converged" is its reason
  bool named = false;
  for (const std::string& reason : r.summary.verdict)
    named = named || reason.find("converged only after") != std::string::npos;
  EXPECT_TRUE(named) << r.summary.verdict[0];
}

}  // namespace
}  // namespace stac
