// The search for a better minimum judges sensors against their seed σ,
// unless the misfit is shared alike by every sensor group (methods/
// alternation.hpp misfitAlike): then the σ's given were too small, and the
// adapted ones are the measure.
#include <gtest/gtest.h>

#include "methods/alternation.hpp"
#include "support/arm_fixture.hpp"

namespace stac {
namespace {

class MisfitAlike : public ::testing::Test {
 protected:
  bool alike(double marker, double joint, double tendon) const {
    GroupScales scales;
    scales.kappa[0] = marker, scales.kappa[1] = joint, scales.kappa[2] = tendon;
    return misfitAlike(problem_, scales);
  }
  test::ArmProblem arm_ = test::makeArmProblem(20, 5);  // markers, pots and a tendon
  MeasurementModel model_{arm_.robot, arm_.sensors};
  NoiseModel seed_ = NoiseModel::fromSeeds(arm_.sensors);
  RobustLoss loss_;
  Problem problem_{model_, arm_.obs, seed_, loss_, 1};
};

TEST_F(MisfitAlike, EveryGroupNoisierThanItsSeedByOneFactor) {
  EXPECT_TRUE(alike(2.5, 2.5, 2.5));
  EXPECT_TRUE(alike(2.0, 2.9, 2.4));  // within 1.5x of each other
}

TEST_F(MisfitAlike, AGroupAtItsNoiseMeansTheMinimumMayBeWrong) {
  // An unseen double pendulum in a mirror image: markers 2.7x, pots 1x.
  EXPECT_FALSE(alike(2.66, 1.0, 2.66));
  EXPECT_FALSE(alike(2.0, 3.1, 2.4));  // not alike: 3.1 > 1.5 x 2.0
  EXPECT_FALSE(alike(1.3, 1.3, 1.3));  // under the escape's bound: no misfit to explain
}

TEST_F(MisfitAlike, OneGroupAloneIsNeverAlike) {
  SensorSet markers_only = arm_.sensors;
  markers_only.joint_sensors.clear();
  markers_only.tendon_sensors.clear();
  const MeasurementModel model(arm_.robot, markers_only);
  const NoiseModel seed = NoiseModel::fromSeeds(markers_only);
  const Problem problem{model, arm_.obs, seed, loss_, 1};
  GroupScales scales;
  scales.kappa[0] = scales.kappa[1] = scales.kappa[2] = 2.5;
  EXPECT_FALSE(misfitAlike(problem, scales));
  // An absent group's κ (left at 1) does not count against the others.
  SensorSet no_tendon = arm_.sensors;
  no_tendon.tendon_sensors.clear();
  const MeasurementModel model2(arm_.robot, no_tendon);
  const NoiseModel seed2 = NoiseModel::fromSeeds(no_tendon);
  const Problem two{model2, arm_.obs, seed2, loss_, 1};
  scales.kappa[2] = 1.0;
  EXPECT_TRUE(misfitAlike(two, scales));
}

}  // namespace
}  // namespace stac
