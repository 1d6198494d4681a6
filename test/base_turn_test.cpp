// A base whose only marker sits far from the limb's root (test/fixtures
// falcon_bravo7_kinematics.urdf: a Bravo 7 arm on a Falcon ROV, the ROV's
// one marker 0.73 m from the arm's first joint): the first stages of the
// tree-order search see that marker and the first links' only, which leave
// the world's half turn about the line through them open, so the search
// also starts from the seed's mocap frame turned so (tree_search.cpp
// seedFrames). Without it, basin truths 6 and 7 of the default draw on
// partial swings ended with the first joints mirrored and the mocap frame
// ~π off, flagged (markers at 3.7x their σ; joint readings at 12x).
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "methods/tree_search.hpp"
#include "stac/calibrate.hpp"
#include "stac/kinematics.hpp"
#include "support/basin_draws.hpp"

namespace stac {
namespace {

test::Robot falcon() {
  return test::externalRobot(
      RobotModel::fromFile(std::string(STAC_SOURCE_DIR) +
                           "/test/fixtures/falcon_bravo7_kinematics.urdf"),
      600);
}

Eigen::Vector3d inMocap(const MocapFrame& f, const Eigen::Vector3d& x) {
  return f.rotation * x + f.translation;
}

// The turned start itself, without a calibration (fast enough for the
// sanitizer pass, which leaves the calibrations below out): the turned
// frame maps the base's marker and the arm's root where the seed's does,
// and differs from it by a half turn.
TEST(BaseTurn, TheSearchAlsoStartsFromTheSeedTurnedAboutTheBaseMarkerAndTheArmsRoot) {
  const test::Robot robot = falcon();
  const MeasurementModel model(robot.model, robot.truth.sensors);
  const SensorParameters& seed = robot.truth.theta;
  const std::vector<SensorParameters> frames = seedFrames(model, seed);
  ASSERT_EQ(frames.size(), 2u);
  EXPECT_TRUE(frames[0].mocap.rotation.isApprox(seed.mocap.rotation));
  const MocapFrame& turned = frames[1].mocap;
  KinematicsWorkspace ws(robot.model);
  forwardKinematics(robot.model, Eigen::VectorXd::Zero(robot.model.dof()), &ws);
  std::vector<Eigen::Vector3d> on_line;
  const SensorSet& s = robot.truth.sensors;
  for (size_t m = 0; m < s.markers.size(); ++m)
    if (robot.model.supportingJoints(s.markers[m].link).empty())
      on_line.push_back(ws.link_pose[s.markers[m].link] * seed.marker_position[m]);
  ASSERT_EQ(on_line.size(), 1u);  // the ROV's one marker
  on_line.push_back(ws.joint_origin[robot.model.qJoints()[0]]);  // the arm's root
  ASSERT_GT((on_line[1] - on_line[0]).norm(), 0.5);
  for (const Eigen::Vector3d& x : on_line)
    EXPECT_LT((inMocap(turned, x) - inMocap(seed.mocap, x)).norm(), 1e-9) << x.transpose();
  const Eigen::Matrix3d relative =
      seed.mocap.rotation.toRotationMatrix().transpose() * turned.rotation.toRotationMatrix();
  EXPECT_NEAR(relative.trace(), -1.0, 1e-9);  // a rotation by π

  // A frame the seed holds is not turned.
  SensorSet held = s;
  held.mocap_frame_fixed.rotation = true;
  EXPECT_EQ(seedFrames(MeasurementModel(robot.model, held), seed).size(), 1u);
}

// Limbs rooted off the line (a quadruped's hips) pin the turn: no second start.
TEST(BaseTurn, AQuadrupedsHipsPinTheTurn) {
  const test::Robot robot = test::externalRobot(
      RobotModel::fromFile(std::string(STAC_SOURCE_DIR) + "/test/fixtures/go1_kinematics.urdf"),
      600);
  const SensorSet& s = robot.truth.sensors;
  // The premise: one base marker, the frame free (so only the hips pin it).
  ASSERT_FALSE(s.mocap_frame_fixed.any());
  int base_markers = 0;
  for (const MarkerConfig& m : s.markers)
    base_markers += robot.model.supportingJoints(m.link).empty();
  ASSERT_EQ(base_markers, 1);
  const MeasurementModel model(robot.model, s);
  EXPECT_EQ(seedFrames(model, robot.truth.theta).size(), 1u);
}

void expectReached(int index) {
  const test::Robot robot = falcon();
  auto [truth, r] = test::replayBasinTruth(robot, test::Variant::kPartialSwings, index,
                                           LossKind::kHuber, CalibrationOptions(), 0, 2024);
  std::string why;
  EXPECT_TRUE(test::closeToTruth(robot.truth.sensors, truth, r, &why)) << index << ": " << why;
  EXPECT_TRUE(r.summary.converged) << index;
  EXPECT_FALSE(r.summary.suspect()) << index << ": " << r.summary.verdict[0];
}

TEST(BaseTurn, AnArmFarFromItsBasesOnlyMarkerIsNotLeftTurnedWithTheWorld) { expectReached(6); }

TEST(BaseTurn, AnArmFarFromItsBasesOnlyMarkerIsNotLeftTurnedWithTheWorldToo) {
  expectReached(7);
}

}  // namespace
}  // namespace stac
