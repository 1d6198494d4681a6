// The world's half turn with a limb's first joint (methods/world_turn.hpp):
// which joints leave it open, and the jumps and the mirror listing that try
// it (wide_basin.cpp, alternation.cpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <utility>

#include "methods/world_turn.hpp"
#include "stac/calibrate.hpp"
#include "support/basin_draws.hpp"

namespace stac {
namespace {

std::string fixture(const std::string& name) {
  return std::string(STAC_SOURCE_DIR) + "/test/fixtures/" + name;
}

// The planar double pendulum: joint 1 turns about x through (0.006, 0,
// 0.035) in the base; a marker on each link, and `base` (a YAML line, or
// nothing) on the base.
std::vector<int> columnsWith(const std::string& base, bool frame_fixed = false) {
  const RobotModel robot =
      RobotModel::fromFile(fixture("double_pendulum_continuous_kinematics.urdf"));
  const std::string yaml = std::string("mocap:\n  sigma: 0.002\n  frame: {fixed: ") +
                           (frame_fixed ? "true" : "false") +
                           "}\n  markers:\n"
                           "    - {name: m1, link: link1, position: [0.01, 0.02, 0.1]}\n"
                           "    - {name: m2, link: link2, position: [0.0, 0.03, 0.2]}\n" +
                           base +
                           "joint_sensors:\n"
                           "  - {name: joint1, joint: joint1, sigma: 0.01}\n"
                           "  - {name: joint2, joint: joint2, sigma: 0.01}\n";
  const SensorsFile s = parseSensorsYaml(yaml, "sensors", robot);
  return worldTurnColumns(MeasurementModel(robot, s.sensors), s.theta);
}

TEST(WorldTurn, OnlyABaseMarkerOffTheFirstJointsAxisPinsTheWorldsHalfTurn) {
  EXPECT_EQ(columnsWith(""), std::vector<int>{0});
  // On joint 1's axis, 0.3 m along it: the turn leaves it in place.
  EXPECT_EQ(columnsWith("    - {name: b, link: base_link, position: [0.3, 0.0, 0.035]}\n"),
            std::vector<int>{0});
  // 5 cm off the axis: turned, it lands 10 cm away.
  EXPECT_TRUE(columnsWith("    - {name: b, link: base_link, position: [0.3, 0.05, 0.035]}\n")
                  .empty());
  // A held mocap frame cannot turn.
  EXPECT_TRUE(columnsWith("", true).empty());
}

// A Bravo 7 on a BlueVolta ROV laid out at random (basin layout 5: no
// marker on the ROV, 6 on the arm, three path tendons), its first joint
// continuous. Plain log, basin truth 8: converged with the mocap frame and
// joint 1 half a turn off, a tendon from the ROV at 2x its σ, absorbed by
// the tendons' adapted σ: verdict ok (silent). Partial swings, truth 1: the
// same, the tendon at 1.35x, below the jumps' mark. Both now reach the
// truth: the jump re-fits the mocap frame to the turned joint, and where
// nothing misfits, the world's half turns are tried alone.
TEST(WorldTurn, ATurnedWorldThatOnlyTheTendonsShowIsLeft) {
  const test::Robot robot = test::externalRobot(
      RobotModel::fromFile(fixture("bluevolta_bravo7_kinematics.urdf")), 600, 5);
  const SensorSet& sensors = robot.truth.sensors;
  ASSERT_EQ(worldTurnColumns(MeasurementModel(robot.model, sensors), robot.truth.theta),
            std::vector<int>{0});
  for (const auto& [variant, index] :
       {std::pair{test::Variant::kPlain, 8}, std::pair{test::Variant::kPartialSwings, 1}}) {
    const auto [truth, r] = test::replayBasinTruth(robot, variant, index);
    std::string why;
    EXPECT_TRUE(test::withinReportedStd(sensors, truth, r, &why)) << index << ": " << why;
    EXPECT_FALSE(r.summary.suspect()) << index << ": " << r.summary.verdict[0];
  }
}

// Partial swings, truth 7: the two turns fit alike to 5e-6 of the cost (no
// tendon's length changes enough over the swing): reported, the mocap
// frame's rotation and joint 1's bias listed with their second value,
// instead of one passed as the answer.
TEST(WorldTurn, AWorldTurnNothingTellsApartIsListed) {
  const test::Robot robot = test::externalRobot(
      RobotModel::fromFile(fixture("bluevolta_bravo7_kinematics.urdf")), 600, 5);
  const auto [truth, r] = test::replayBasinTruth(robot, test::Variant::kPartialSwings, 7);
  std::string why;
  EXPECT_TRUE(test::withinReportedStd(robot.truth.sensors, truth, r, &why)) << why;
  const UnidentifiableDirection* turn = nullptr;
  for (const UnidentifiableDirection& d : r.summary.unidentifiable)
    if (d.reason.find("mocap frame turned half a turn about joint1") != std::string::npos)
      turn = &d;
  ASSERT_NE(turn, nullptr);
  EXPECT_EQ(turn->kind, Undetermined::kMirror);
  const auto listed = [&](const std::string& name) {
    return std::find(turn->parameters.begin(), turn->parameters.end(), name) !=
           turn->parameters.end();
  };
  EXPECT_TRUE(listed("joint_sensors.joint1.bias"));
  EXPECT_FALSE(r.summary.suspect()) << r.summary.verdict[0];
}

}  // namespace
}  // namespace stac
