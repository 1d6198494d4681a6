// A jump out of a wrong minimum goes on from the start it was scored from.
// humanoid38/partial basin truth 13 converged with its left foot folded
// (the ankle's roll pot a half turn off, the toe's gain collapsed to 0.04
// against 1.39); the escape found the ankle's flip clearly better on the
// subsample (refined from one q-phase, then θ). θ alone re-fitted to the
// moved angles on the whole log, the run went to another folded minimum and
// stopped unconverged at 200 iterations (flagged, a miss); from one
// alternation (q, then θ) it reaches the truth. ~60 s: label long (the
// basin test covers it too, STAC_BASIN_PICK=13).
#include <gtest/gtest.h>

#include <string>

#include "stac/calibrate.hpp"
#include "support/basin_draws.hpp"

namespace stac {
namespace {

TEST(EscapeStart, AFoldedAnkleIsLeftFromTheStartItsJumpWasScoredFrom) {
  const test::Robot humanoid = test::bundledRobot("humanoid38", 500);  // as the basin test
  const auto [truth, r] = test::replayBasinTruth(humanoid, test::Variant::kPartialSwings, 13);
  std::string why;
  EXPECT_TRUE(test::closeToTruth(humanoid.truth.sensors, truth, r, &why)) << why;
  EXPECT_TRUE(r.summary.converged) << r.summary.iterations << " iterations";
  EXPECT_FALSE(r.summary.suspect()) << r.summary.verdict[0];
}

}  // namespace
}  // namespace stac
