// Variance adaptation (noise_adaptation.hpp): the estimate of a long log's
// group is its residuals' mean square per residual dof; a group with no
// residual dof left (the q_t fit it exactly) stays at its seed instead of
// collapsing; θ's free entries count against the group they shape.
#include "solve/noise_adaptation.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "stac/theta_space.hpp"
#include "support/arm_fixture.hpp"

namespace stac {
namespace {

TEST(NoiseAdaptation, LongLogGroupTakesItsResidualsMeanSquare) {
  GroupResiduals r;
  r.wsse[0] = 4.0 * 1e6;  // κ² = 4 over a million residual dof
  r.dofs[0] = 1e6;
  GroupScales scales;
  updateScales(r, false, &scales);
  EXPECT_NEAR(scales.kappa[0], 2.0, 1e-4);
  EXPECT_EQ(scales.kappa[1], 1.0);  // no rows: unchanged
}

TEST(NoiseAdaptation, GroupFitExactlyDoesNotCollapse) {
  // A group the q_t fit exactly: nearly no residual, nearly no dof left.
  // Without the seed's weight, κ = sqrt(1e-8 / 1) = 1e-4 and, iterated, σ
  // drifts to 0; with it κ stays near its seed.
  GroupResiduals r;
  r.wsse[0] = 1e-8;
  r.dofs[0] = 1.0;
  GroupScales scales;
  for (int it = 0; it < 50; ++it) updateScales(r, true, &scales);
  EXPECT_GT(scales.kappa[0], 0.9);
  EXPECT_LE(scales.kappa[0], 1.0);
}

TEST(NoiseAdaptation, FreeThetaEntriesCountAgainstTheirGroup) {
  test::ArmProblem p = test::makeArmProblem(5, 1);
  SensorSet s = p.sensors;
  ASSERT_GE(s.markers.size(), 2u);
  ASSERT_GE(s.joint_sensors.size(), 2u);
  for (auto& m : s.markers) m.fixed = false;
  for (auto& j : s.joint_sensors) j.fixed = FixedGainBias::both(false);
  for (auto& t : s.tendon_sensors) t.fixed = FixedGainBias::both(false);
  s.mocap_frame_fixed = FixedFrame::both(false);
  const int M = static_cast<int>(s.markers.size());
  const int J = static_cast<int>(s.joint_sensors.size());
  const int N = static_cast<int>(s.tendon_sensors.size());
  EXPECT_EQ(ThetaSpace(s).freeInGroup(SensorGroup::kMarker), 6 + 3 * M);
  EXPECT_EQ(ThetaSpace(s).freeInGroup(SensorGroup::kJoint), 2 * J);
  EXPECT_EQ(ThetaSpace(s).freeInGroup(SensorGroup::kTendon), 2 * N);
  s.markers[0].fixed = true;
  s.mocap_frame_fixed.rotation = true;
  s.joint_sensors[1].fixed.gain = true;
  EXPECT_EQ(ThetaSpace(s).freeInGroup(SensorGroup::kMarker), 3 + 3 * (M - 1));
  EXPECT_EQ(ThetaSpace(s).freeInGroup(SensorGroup::kJoint), 2 * J - 1);
}

}  // namespace
}  // namespace stac
