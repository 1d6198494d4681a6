// Mirror configurations the data cannot tell apart (mirror_ambiguity.hpp):
// a chain whose axes 1 and 3 align at q2 = 0 passes through the same places
// with q1 + π, −q2, q3 + π. With the markers of links 1 and 2 free and a
// motion that fits within the limits either way, the two fit alike: the
// result lists the pots' parameters as undetermined; a marker held on link
// 2 tells them apart, and then nothing is listed.
#include "methods/mirror_ambiguity.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <string>

#include "methods/wide_basin.hpp"
#include "stac/calibrate.hpp"
#include "stac/sensors_file.hpp"
#include "stac/simulate.hpp"
#include "support/chain_fixture.hpp"

namespace stac {
namespace {

// j1 and j3 over [-0.5, 0.7] only: half a turn away fits the limits too.
struct Chain : test::ChainLog {
  explicit Chain(bool l2_held) : ChainLog(l2_held, 3, {{0, -0.5, 0.7}, {2, -0.5, 0.7}}) {}
};

bool listsTheMirror(const std::vector<UnidentifiableDirection>& dirs) {
  return std::any_of(dirs.begin(), dirs.end(), [](const UnidentifiableDirection& d) {
    return d.reason.find("j1 and j3 half a turn away with j2 mirrored") != std::string::npos &&
           std::find(d.parameters.begin(), d.parameters.end(), "joint_sensors.j2_pot.gain") !=
               d.parameters.end();
  });
}

// Calibrated from the truth and its angles (no initialisation).
CalibrationResult calibrateFromTheTruth(const Chain& c) {
  CalibrationOptions o;
  o.threads = 2;
  return calibrate(c.robot, c.truth.sensors, c.truth.theta, c.obs, o, nullptr, &c.q);
}

TEST(MirrorAmbiguity, TheWristFlipFitsAlikeWithTheMiddleMarkersFree) {
  const Chain c(false);
  const NoiseModel noise = NoiseModel::fromSeeds(c.truth.sensors);
  const RobustLoss loss;
  Workspaces ws = makeWorkspaces(c.model, 2);
  const WideBasin basin(c.model, c.obs, noise, loss, 2, &ws, c.truth.theta, false);
  Estimate est;
  est.theta = c.truth.theta;
  est.state.q = c.q;
  const std::vector<MinimumMove> same = basin.equivalentMoves(est);
  ASSERT_EQ(same.size(), 1u);
  EXPECT_EQ(same[0].flip, std::vector<int>{1});
  EXPECT_EQ(same[0].half_turn, (std::vector<int>{0, 2}));
}

TEST(MirrorAmbiguity, ACalibrationListsIt) {
  const CalibrationResult r = calibrateFromTheTruth(Chain(false));
  EXPECT_TRUE(listsTheMirror(r.summary.unidentifiable));
}

TEST(MirrorAmbiguity, AMarkerHeldOnALinkInBetweenTellsThemApart) {
  const CalibrationResult r = calibrateFromTheTruth(Chain(true));
  EXPECT_FALSE(listsTheMirror(r.summary.unidentifiable));
  EXPECT_TRUE(r.summary.unidentifiable.empty()) << r.summary.unidentifiable[0].reason;
  EXPECT_FALSE(r.summary.suspect()) << r.summary.verdict[0];
}

}  // namespace
}  // namespace stac
