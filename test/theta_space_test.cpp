// The θ space: layout, names, free mask, ⊕ / ⊖ on the rotation manifold.
#include "stac/theta_space.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>

#include "support/arm_fixture.hpp"

namespace stac {
namespace {

SensorParameters randomTheta(const SensorSet& s, std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  SensorParameters th;
  th.mocap.rotation = Eigen::Quaterniond(n(rng), n(rng), n(rng), n(rng)).normalized();
  th.mocap.translation = Eigen::Vector3d(n(rng), n(rng), n(rng));
  for (size_t m = 0; m < s.markers.size(); ++m)
    th.marker_position.push_back(0.1 * Eigen::Vector3d(n(rng), n(rng), n(rng)));
  for (size_t j = 0; j < s.joint_sensors.size(); ++j) th.joint_sensor.push_back({n(rng), n(rng)});
  for (size_t j = 0; j < s.tendon_sensors.size(); ++j) th.tendon_sensor.push_back({n(rng), n(rng)});
  return th;
}

TEST(ThetaSpace, LayoutNamesAndEntries) {
  const test::ArmProblem p = test::makeArmProblem(5, 1);
  const ThetaSpace space(p.sensors);
  const int M = static_cast<int>(p.sensors.markers.size());
  const int J = static_cast<int>(p.sensors.joint_sensors.size());
  const int N = static_cast<int>(p.sensors.tendon_sensors.size());
  ASSERT_EQ(space.size(), 6 + 3 * M + 2 * J + 2 * N);
  ASSERT_EQ(static_cast<int>(space.names().size()), space.size());
  EXPECT_EQ(space.names()[0], "mocap.frame.rotation.x");
  EXPECT_EQ(space.names()[5], "mocap.frame.translation.z");
  EXPECT_EQ(space.names()[space.markerOffset(1) + 2],
            "markers." + p.sensors.markers[1].name + ".position.z");
  EXPECT_EQ(space.names()[space.jointOffset(2) + 1],
            "joint_sensors." + p.sensors.joint_sensors[2].name + ".bias");
  EXPECT_EQ(space.names()[space.tendonOffset(0)],
            "tendon_sensors." + p.sensors.tendon_sensors[0].name + ".gain");
  // entry() inverts the offsets for every index.
  for (int i = 0; i < space.size(); ++i) {
    const ThetaEntry e = space.entry(i);
    switch (e.block) {
      case ThetaBlock::kMocapRotation: EXPECT_EQ(i, e.component); break;
      case ThetaBlock::kMocapTranslation: EXPECT_EQ(i, 3 + e.component); break;
      case ThetaBlock::kMarker: EXPECT_EQ(i, space.markerOffset(e.item) + e.component); break;
      case ThetaBlock::kJointSensor: EXPECT_EQ(i, space.jointOffset(e.item) + e.component); break;
      case ThetaBlock::kTendonSensor: EXPECT_EQ(i, space.tendonOffset(e.item) + e.component); break;
      case ThetaBlock::kJointOrigin: EXPECT_EQ(i, space.originOffset(e.item) + e.component); break;
    }
  }
  EXPECT_EQ(space.ownerKey(1), "mocap.frame.rotation");
  EXPECT_EQ(space.ownerPhrase(space.markerOffset(0) + 1),
            "marker " + p.sensors.markers[0].name + " position");
  EXPECT_EQ(space.ownerPhrase(space.jointOffset(1) + 1),
            "bias of " + p.sensors.joint_sensors[1].name);
  EXPECT_EQ(space.ownerKey(space.jointOffset(1)),
            "joint_sensors." + p.sensors.joint_sensors[1].name + ".gain");
}

TEST(ThetaSpace, FreeMaskFollowsFixed) {
  test::ArmProblem p = test::makeArmProblem(5, 1);
  p.sensors.joint_sensors[1].fixed = FixedGainBias::both(true);
  p.sensors.mocap_frame_fixed = FixedFrame::both(true);
  const ThetaSpace space(p.sensors);
  int fixed_markers = 0;
  for (const MarkerConfig& m : p.sensors.markers) fixed_markers += m.fixed;
  EXPECT_EQ(space.freeSize(), space.size() - 6 - 3 * fixed_markers - 2);
  for (int i = 0; i < space.size(); ++i) {
    const ThetaEntry e = space.entry(i);
    const bool fixed = e.block == ThetaBlock::kMocapRotation ||
                       e.block == ThetaBlock::kMocapTranslation ||
                       (e.block == ThetaBlock::kMarker && p.sensors.markers[e.item].fixed) ||
                       (e.block == ThetaBlock::kJointSensor && e.item == 1);
    EXPECT_EQ(space.free()[i], !fixed) << space.names()[i];
    EXPECT_EQ(space.freePosition()[i] >= 0, !fixed);
    if (!fixed) {
      EXPECT_EQ(space.freeIndex()[space.freePosition()[i]], i);
    }
  }
  // A step over the free entries leaves the fixed ones exactly alone.
  std::mt19937 rng(3);
  const SensorParameters th = randomTheta(p.sensors, rng);
  const SensorParameters moved = space.plusFree(th, Eigen::VectorXd::Ones(space.freeSize()));
  EXPECT_EQ(moved.joint_sensor[1].gain, th.joint_sensor[1].gain);
  EXPECT_TRUE(moved.mocap.rotation.coeffs() == th.mocap.rotation.coeffs());
  EXPECT_NE(moved.joint_sensor[0].gain, th.joint_sensor[0].gain);
  // No markers: the mocap frame is not a parameter.
  SensorSet no_markers = p.sensors;
  no_markers.markers.clear();
  no_markers.mocap_frame_fixed = FixedFrame::both(false);
  EXPECT_FALSE(ThetaSpace(no_markers).free()[0]);
}

TEST(ThetaSpace, PlusMinusRoundTrip) {
  const test::ArmProblem p = test::makeArmProblem(5, 2);
  const ThetaSpace space(p.sensors);
  std::mt19937 rng(7);
  std::normal_distribution<double> n(0.0, 0.3);
  for (int trial = 0; trial < 20; ++trial) {
    const SensorParameters a = randomTheta(p.sensors, rng);
    Eigen::VectorXd delta(space.size());
    for (int i = 0; i < space.size(); ++i) delta[i] = n(rng);
    const SensorParameters b = space.plus(a, delta);
    // (a ⊕ δ) ⊖ a = δ, rotation included (|δ_rot| < π).
    EXPECT_LT((space.minus(b, a) - delta).norm(), 1e-12) << trial;
    // a ⊕ (b ⊖ a) = b.
    const SensorParameters c = space.plus(a, space.minus(b, a));
    EXPECT_LT(space.minus(c, b).norm(), 1e-12);
    EXPECT_LT(c.mocap.rotation.angularDistance(b.mocap.rotation), 1e-12);
    // The rotation turns on the left: R_b = exp([δ]×) R_a.
    const Eigen::Vector3d w = delta.head<3>();
    const Eigen::Matrix3d expected =
        Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix() *
        a.mocap.rotation.toRotationMatrix();
    EXPECT_LT((b.mocap.rotation.toRotationMatrix() - expected).norm(), 1e-12);
    // value() reads what plus() moved.
    for (int i = 3; i < space.size(); ++i)
      EXPECT_NEAR(space.value(b, i) - space.value(a, i), delta[i], 1e-12) << space.names()[i];
  }
}

TEST(ThetaSpace, ExpandFreeAndStd) {
  test::ArmProblem p = test::makeArmProblem(5, 1);
  p.sensors.tendon_sensors[0].fixed = FixedGainBias::both(true);
  const ThetaSpace space(p.sensors);
  Eigen::VectorXd values(space.freeSize());
  for (int i = 0; i < space.freeSize(); ++i) values[i] = i + 1;
  const Eigen::VectorXd full = space.expandFree(values);
  for (int i = 0; i < space.size(); ++i)
    EXPECT_EQ(full[i], space.free()[i] ? space.freePosition()[i] + 1.0 : 0.0);
  const ParameterStd sd = space.toParameterStd(full);
  EXPECT_EQ(sd.mocap_rotation[2], full[2]);
  EXPECT_EQ(sd.mocap_translation[0], full[3]);
  EXPECT_EQ(sd.marker_position[1][2], full[space.markerOffset(1) + 2]);
  EXPECT_EQ(sd.joint_sensor[3].bias, full[space.jointOffset(3) + 1]);
  EXPECT_EQ(sd.tendon_sensor[0].gain, 0.0);
  // Scales: positive, gains' through their own magnitude.
  std::mt19937 rng(5);
  const SensorParameters th = randomTheta(p.sensors, rng);
  const Eigen::VectorXd scale = space.scale(th);
  EXPECT_TRUE((scale.array() > 0).all());
  EXPECT_DOUBLE_EQ(scale[space.jointOffset(0)],
                   0.1 * std::max(std::abs(th.joint_sensor[0].gain), 1e-3));
}

}  // namespace
}  // namespace stac
