// A pot on a joint the log holds still (still_joints.hpp): its readings
// vary by their noise alone, so its gain (and its bias with it) is not in
// the data. The result lists both as undetermined, with an infinite std and
// a reason naming the joint; the rest still reaches the truth and the
// verdict is ok. A joint that moves, however little beyond its pot's
// noise, is not listed.
#include "methods/still_joints.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "stac/calibrate.hpp"
#include "support/basin_draws.hpp"
#include "support/chain_fixture.hpp"

namespace stac {
namespace {

bool listsStillPot(const std::vector<UnidentifiableDirection>& dirs, const std::string& pot,
                   const std::string& joint) {
  return std::any_of(dirs.begin(), dirs.end(), [&](const UnidentifiableDirection& d) {
    const auto has = [&](const std::string& p) {
      return std::find(d.parameters.begin(), d.parameters.end(), p) != d.parameters.end();
    };
    return has("joint_sensors." + pot + ".gain") && has("joint_sensors." + pot + ".bias") &&
           d.reason.find("does not move joint " + joint) != std::string::npos;
  });
}

// `sensors` with every pot's seed σ divided by k.
SensorSet potSigmaOver(const SensorSet& sensors, double k) {
  SensorSet out = sensors;
  for (JointSensorConfig& js : out.joint_sensors) js.sigma /= k;
  return out;
}

NoiseModel potSigmaTimes(NoiseModel noise, double k) {
  for (double& s : noise.joint) s *= k;
  return noise;
}

// The chain calibrated under `sensors` from the paper's seeding of the
// pots: j2's pot listed undetermined with an infinite std, the rest within
// its reported std of the truth, verdict ok.
void expectCalibratedWithTheStillPotListed(const test::ChainLog& c, const SensorSet& sensors) {
  CalibrationOptions o;
  o.threads = 2;
  SensorParameters start = c.truth.theta;
  for (GainBias& gb : start.joint_sensor) gb = {1.0, 0.0};
  const CalibrationResult r = calibrate(c.robot, sensors, start, c.obs, o);
  EXPECT_TRUE(listsStillPot(r.summary.unidentifiable, "j2_pot", "j2"));
  EXPECT_TRUE(std::isinf(r.std.joint_sensor[1].gain));
  EXPECT_TRUE(std::isinf(r.std.joint_sensor[1].bias));
  std::string why;
  EXPECT_TRUE(test::withinReportedStd(c.truth.sensors, c.truth.theta, r, &why)) << why;
  EXPECT_FALSE(r.summary.suspect()) << r.summary.verdict[0];
}

// The chain with j2 held at 0.3 rad: its pot reads 2.1 * 0.3 - 0.7 plus
// noise of σ 0.01 in every frame.
TEST(StillJoint, APotOnAJointTheLogHoldsStillHasItsGainAndBiasListedUndetermined) {
  const test::ChainLog c(true, 3, {{1, 0.3, 0.3}});
  const NoiseModel seed = NoiseModel::fromSeeds(c.truth.sensors);
  const auto listed = stillJoints(c.model, c.obs, seed, seed);
  ASSERT_EQ(listed.size(), 1u);
  EXPECT_TRUE(listsStillPot(listed, "j2_pot", "j2"));
  EXPECT_EQ(listed[0].kind, Undetermined::kStillJoint);
  expectCalibratedWithTheStillPotListed(c, c.truth.sensors);
}

// A seed σ half the pots' noise (within the verdict's 3x, so the run is
// not suspect for it): the still pot's readings vary by twice its seed σ
// and the seed's alone does not list it: its gain kept a sharp local std
// that nothing in the data backs (near the truth here; the unseen
// quadruped's still knee read 0.17 ± 0.015 against 1.86). The fit's group
// factor brings the pots' σ back to their noise, and the larger of the two
// lists the pot.
TEST(StillJoint, ASeedSigmaTooSmallForTheGroupDoesNotHideAStillPot) {
  const test::ChainLog c(true, 3, {{1, 0.3, 0.3}});
  const SensorSet small = potSigmaOver(c.truth.sensors, 2);
  const NoiseModel seed = NoiseModel::fromSeeds(small);
  EXPECT_TRUE(stillJoints(MeasurementModel(c.robot, small), c.obs, seed, seed).empty());
  expectCalibratedWithTheStillPotListed(c, small);
}

// The bound's σ directly: the fitted σ counts where it is larger than the
// seed's, up to twice it; a smaller one does not shrink the bound.
TEST(StillJoint, TheBoundsSigmaIsTheSeedsOrTheFittedUpToTwiceTheSeeds) {
  const test::ChainLog c(true, 3, {{1, 0.3, 0.3}});
  const SensorSet small = potSigmaOver(c.truth.sensors, 2);
  const MeasurementModel model(c.robot, small);
  const NoiseModel seed = NoiseModel::fromSeeds(small);
  EXPECT_TRUE(
      listsStillPot(stillJoints(model, c.obs, seed, potSigmaTimes(seed, 2)), "j2_pot", "j2"));
  EXPECT_TRUE(stillJoints(model, c.obs, seed, NoiseModel()).empty());
  EXPECT_TRUE(stillJoints(model, c.obs, seed, potSigmaTimes(seed, 0.5)).empty());
  // Readings spreading 3.3x the seed σ (as a joint that moves would) are
  // not listed by a fitted σ 3x the seed's, the most the verdict lets pass
  // (uncapped, the bound would be 3.75x).
  const SensorSet tight = potSigmaOver(c.truth.sensors, 3.3);
  const NoiseModel seed_tight = NoiseModel::fromSeeds(tight);
  EXPECT_TRUE(stillJoints(MeasurementModel(c.robot, tight), c.obs, seed_tight,
                          potSigmaTimes(seed_tight, 3))
                  .empty());
}

// j2 over 0.3..0.32 rad only: its readings spread about 1.5x the pot's
// σ, a motion of the size of the noise that 400 frames see (the bundled
// hand's narrow abductions on partial swings read 1.75-2x); not listed.
TEST(StillJoint, AJointThatMovesByAboutItsPotsNoiseIsNotListed) {
  const test::ChainLog c(true, 3, {{1, 0.3, 0.32}});
  const Eigen::ArrayXd p = c.obs.joint.col(1).array();
  const double spread = std::sqrt((p - p.mean()).square().mean());
  EXPECT_GT(spread, 1.3 * 0.01);
  EXPECT_LT(spread, 2.0 * 0.01);
  const NoiseModel seed = NoiseModel::fromSeeds(c.truth.sensors);
  EXPECT_TRUE(stillJoints(c.model, c.obs, seed, seed).empty());
}

// A held gain or bias pins the other from the readings' level: not listed.
TEST(StillJoint, APotWithAHeldGainIsNotListed) {
  const test::ChainLog c(true, 3, {{1, 0.3, 0.3}});
  SensorSet held = c.truth.sensors;
  held.joint_sensors[1].fixed.gain = true;
  const MeasurementModel model(c.robot, held);
  const NoiseModel seed = NoiseModel::fromSeeds(held);
  EXPECT_TRUE(stillJoints(model, c.obs, seed, seed).empty());
}

}  // namespace
}  // namespace stac
