// Calibrated URDF (urdf_patch.hpp): the patched marker links' forward
// kinematics equal the calibrated markers' h_k(q) d on the original model,
// nothing else moves, the text changes only in the written xyz values (and
// the one inserted <origin>), and markers without a link of their own are
// listed with the reason.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <random>
#include <regex>
#include <set>
#include <sstream>

#include "stac/error.hpp"
#include "stac/kinematics.hpp"
#include "stac/robot_model.hpp"
#include "stac/urdf_patch.hpp"
#include "support/test_util.hpp"

namespace stac {
namespace {

// Comments (one hiding a <joint>), tabs, single quotes, attributes in odd
// order and spacing, elements on one line: all must survive byte for byte.
const char* kUrdf = R"(<?xml version="1.0"?>
<!-- Test arm with marker links. <joint name="mk_a_joint"><origin xyz="9 9 9"/></joint> -->
<robot name="patch_arm">
  <link name="base"/>
  <link name="l1"/>
  <link name="l2"/>
  <link name="mk_a"/>
  <link name="mk_b_mount"/>
  <link name="mk_b"/>
  <link name="mk_c"/>
  <link name="tool"/>
  <link name="mk_g"/>
  <link name="mk_h"/>
  <link name="mk_h_child"/>
  <link name="mk_i"/>
  <link name="mk_j"/>
  <link name="mk_k"/>
  <joint name="j1" type="revolute">
    <parent link="base"/>  <child link="l1"/>
    <origin xyz="0 0 0.1" rpy="0 0 0"/>
    <axis xyz="0 0 1"/>
    <limit lower="-2" upper="2" effort="1" velocity="1"/>
  </joint>
  <joint name="j2" type="revolute">
    <parent link="l1"/>
    <child link="l2"/>
    <origin xyz="0.3 0 0" rpy="0.2 -0.1 0.4"/>
    <axis xyz="0 1 0"/>
    <limit lower="-2" upper="2" effort="1" velocity="1"/>
  </joint>
  <!-- mk_a: the marker's own link -->
  <joint name="mk_a_joint" type="fixed">
	<parent link="l1"/>
	<child link="mk_a"/>
	<origin   rpy = '0.3 -0.2 1.1'   xyz = '0.1 0.02 0.03' />
  </joint>
  <joint name="mk_b_mount_joint" type="fixed">
    <parent link="l2"/>
    <child link="mk_b_mount"/>
    <origin xyz="0.05 0 0.02" rpy="0 1.5707963267948966 0"/>
  </joint>
  <joint name="mk_b_joint" type="fixed">
    <parent link="mk_b_mount"/>
    <child link="mk_b"/>
    <origin xyz="0.01 0.01 0.01" rpy="0.5 0 0"/>
  </joint>
  <joint name="mk_c_joint" type="fixed">
    <parent link="l2"/>
    <child link="mk_c"/>
  </joint>
  <joint name="tool_joint" type="fixed"> <parent link="l2"/> <child link="tool"/> <origin xyz="0.2 0 0"/> </joint>
  <joint name="mk_g_joint" type="revolute">
    <parent link="l2"/>
    <child link="mk_g"/>
    <axis xyz="1 0 0"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/>
  </joint>
  <joint name="mk_h_joint" type="fixed">
    <parent link="l1"/>
    <child link="mk_h"/>
    <origin xyz="0 0.1 0"/>
  </joint>
  <joint name="mk_h_child_joint" type="fixed">
    <parent link="mk_h"/>
    <child link="mk_h_child"/>
  </joint>
  <joint name="mk_i_joint" type="fixed">
    <parent link="l1"/>
    <child link="mk_i"/>
    <origin rpy="0 0 0.5"/>
  </joint>
  <joint name="mk_j_joint" type="fixed">
    <parent link="l2"/>
    <child link="mk_j"/>
    <origin xyz="0 0 0.3"/>
  </joint>
  <joint name="mk_k_joint" type="fixed">
    <parent link="l2"/>
    <child link="mk_k"/>
    <origin xyz="0 0.2 0"/>
  </joint>
  <transmission name="t1"><joint name="mk_a_joint"/></transmission>
</robot>
)";

struct PatchArm {
  RobotModel robot = RobotModel::fromString(kUrdf, "patch_arm.urdf");
  SensorSet sensors;
  SensorParameters theta;

  PatchArm() {
    auto marker = [&](const std::string& name, const std::string& link, Eigen::Vector3d d) {
      MarkerConfig m;
      m.name = name;
      m.link_name = link;
      m.link = *robot.linkIndex(link);
      sensors.markers.push_back(m);
      theta.marker_position.push_back(d);
    };
    marker("mk_a", "mk_a", {0.011, -0.022, 0.033});  // own link
    marker("mk_b", "l2", {0.12, 0.03, -0.04});       // named link, two fixed joints down
    marker("mk_c", "l2", {-0.05, 0.06, 0.07});       // named link, joint without <origin>
    marker("mk_d", "l1", {0.1, 0.0, 0.0});           // no such link
    marker("mk_e", "tool", {0.01, 0.0, 0.0});        // tool carries two markers
    marker("mk_f", "tool", {0.0, 0.01, 0.0});
    marker("mk_g", "l2", {0.0, 0.0, 0.1});           // its link moves
    marker("mk_h", "l1", {0.0, 0.1, 0.01});          // its link has a child
    marker("mk_i", "mk_i", {0.02, 0.03, -0.01});     // own link, <origin> without xyz
    marker("mk_j", "l1", {0.05, 0.0, 0.0});          // its link is on another body
    marker("mk_k", "mk_k", {0.0, 0.0, 0.01});        // its link anchors a tendon
    TendonSensorConfig t;
    t.name = "cyl";
    t.path = {{"l1", *robot.linkIndex("l1"), Eigen::Vector3d(0, 0, 0.1)},
              {"mk_k", *robot.linkIndex("mk_k"), Eigen::Vector3d::Zero()}};
    sensors.tendon_sensors.push_back(t);
    theta.tendon_sensor.push_back({});
  }
};

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);) out.push_back(l);
  return out;
}

TEST(UrdfPatch, MarkerLinksLandOnTheCalibratedMarkers) {
  const PatchArm s;
  const UrdfPatch p = patchUrdfMarkers(kUrdf, s.robot, s.sensors, s.theta, "patch_arm.urdf");
  std::set<std::string> placed;
  for (const PlacedMarker& m : p.placed) placed.insert(m.marker);
  EXPECT_EQ(placed, (std::set<std::string>{"mk_a", "mk_b", "mk_c", "mk_i"}));
  const RobotModel patched = RobotModel::fromString(p.urdf, "patched.urdf");
  ASSERT_EQ(patched.dof(), s.robot.dof());
  ASSERT_EQ(patched.numLinks(), s.robot.numLinks());

  std::mt19937 rng(7);
  KinematicsWorkspace wa(s.robot), wb(patched);
  for (int trial = 0; trial < 20; ++trial) {
    const Eigen::VectorXd q = test::randomQ(s.robot, rng);
    forwardKinematics(s.robot, q, &wa);
    forwardKinematics(patched, q, &wb);
    std::set<std::string> moved;
    for (size_t m = 0; m < s.sensors.markers.size(); ++m) {
      if (!placed.count(s.sensors.markers[m].name)) continue;
      // h_k(q) d on the original model vs. the marker link's origin.
      const Eigen::Vector3d expected =
          wa.link_pose[s.sensors.markers[m].link] * s.theta.marker_position[m];
      const int L = *patched.linkIndex(s.sensors.markers[m].name);
      EXPECT_LT((wb.link_pose[L].translation() - expected).norm(), 1e-12)
          << s.sensors.markers[m].name;
      moved.insert(s.sensors.markers[m].name);
    }
    // Every other link keeps its pose; the marker links keep their rotation.
    for (int l = 0; l < s.robot.numLinks(); ++l) {
      const std::string& name = s.robot.links()[l].name;
      const Eigen::Isometry3d& A = wa.link_pose[l];
      const Eigen::Isometry3d& B = wb.link_pose[*patched.linkIndex(name)];
      EXPECT_LT((A.linear() - B.linear()).norm(), 1e-12) << name;
      if (!moved.count(name)) {
        EXPECT_LT((A.translation() - B.translation()).norm(), 1e-12) << name;
      }
    }
  }
}

TEST(UrdfPatch, OnlyTheWrittenValuesChange) {
  const PatchArm s;
  const UrdfPatch p = patchUrdfMarkers(kUrdf, s.robot, s.sensors, s.theta, "patch_arm.urdf");
  const std::vector<std::string> a = lines(kUrdf), b = lines(p.urdf);
  const std::regex xyz(R"(xyz\s*=\s*(['"])[^'"]*\1)");
  const std::regex inserted(R"(^    <origin xyz="[-0-9.e]+ [-0-9.e]+ [-0-9.e]+"/>$)");
  std::vector<std::string> changed, added;
  size_t j = 0;
  for (size_t i = 0; i < a.size(); ++i, ++j) {
    ASSERT_LT(j, b.size());
    if (a[i] == b[j]) continue;
    if (std::regex_match(b[j], inserted) && j + 1 < b.size() && a[i] == b[j + 1]) {
      added.push_back(a[i]);  // the line the <origin> went before
      ++j;
      continue;
    }
    // A changed line differs only inside an xyz="..." (or a new one).
    const std::string ma = std::regex_replace(a[i], xyz, "xyz=$1$1");
    const std::string mb = std::regex_replace(b[j], xyz, "xyz=$1$1");
    EXPECT_TRUE(ma == mb || std::regex_replace(mb, std::regex(R"( xyz="")"), "") == ma)
        << "line " << i + 1 << ":\n  " << a[i] << "\n  " << b[j];
    changed.push_back(a[i]);
  }
  EXPECT_EQ(j, b.size());
  // mk_a (single quotes kept), mk_b, and mk_i (xyz added to its <origin>).
  ASSERT_EQ(changed.size(), 3u);
  EXPECT_EQ(changed[0], "\t<origin   rpy = '0.3 -0.2 1.1'   xyz = '0.1 0.02 0.03' />");
  EXPECT_NE(p.urdf.find("\t<origin   rpy = '0.3 -0.2 1.1'   xyz = '"), std::string::npos);
  EXPECT_EQ(changed[1], "    <origin xyz=\"0.01 0.01 0.01\" rpy=\"0.5 0 0\"/>");
  EXPECT_EQ(changed[2], "    <origin rpy=\"0 0 0.5\"/>");
  // mk_c's <origin>, indented like its siblings, before its <parent>.
  ASSERT_EQ(added.size(), 1u);
  EXPECT_EQ(added[0], "    <parent link=\"l2\"/>");
  // The placed joint's line in the input (not the commented-out one).
  const std::string text = kUrdf;
  const size_t at = text.find("<joint name=\"mk_a_joint\" type");
  for (const PlacedMarker& m : p.placed)
    if (m.marker == "mk_a") {
      EXPECT_EQ(m.line, 1 + std::count(text.begin(), text.begin() + at, '\n'));
    }
}

TEST(UrdfPatch, UnplaceableMarkersAreListedWithTheReason) {
  const PatchArm s;
  const UrdfPatch p = patchUrdfMarkers(kUrdf, s.robot, s.sensors, s.theta, "patch_arm.urdf");
  std::map<std::string, std::string> reason;
  for (const UnplacedMarker& u : p.unplaced) reason[u.marker] = u.reason;
  ASSERT_EQ(reason.size(), 7u);
  auto has = [&](const std::string& m, const std::string& what) {
    ASSERT_TRUE(reason.count(m)) << m;
    EXPECT_NE(reason[m].find(what), std::string::npos) << m << ": " << reason[m];
  };
  has("mk_d", "no link named 'mk_d'");
  has("mk_d", "link 'l1' is attached by the movable joint 'j1'");
  has("mk_e", "link 'tool' also carries marker 'mk_f'");
  has("mk_f", "link 'tool' also carries marker 'mk_e'");
  has("mk_g", "link 'mk_g' is attached by the movable joint 'mk_g_joint'");
  has("mk_h", "link 'mk_h' has child links");
  has("mk_j", "link 'mk_j' is not fixed to link 'l1'");
  has("mk_k", "tendon sensor 'cyl'");
}

TEST(UrdfPatch, UnchangedPositionsLeaveTheTextAlone) {
  PatchArm s;
  // mk_a at its link origin: T_J * 0 is the written origin, exactly. mk_i's
  // origin has no xyz (0 0 0) and the marker is at 0.
  s.theta.marker_position[0].setZero();
  s.theta.marker_position[8].setZero();
  const UrdfPatch p = patchUrdfMarkers(kUrdf, s.robot, s.sensors, s.theta, "patch_arm.urdf");
  EXPECT_NE(p.urdf.find("xyz = '0.1 0.02 0.03'"), std::string::npos);
  EXPECT_NE(p.urdf.find("    <origin rpy=\"0 0 0.5\"/>\n"), std::string::npos);
  // With only unplaceable markers nothing changes at all.
  const PatchArm none;
  SensorSet only_d;
  only_d.markers = {none.sensors.markers[3]};
  SensorParameters theta_d;
  theta_d.marker_position = {none.theta.marker_position[3]};
  EXPECT_EQ(patchUrdfMarkers(kUrdf, none.robot, only_d, theta_d).urdf, kUrdf);
}

TEST(UrdfPatch, ErrorsNameTheLine) {
  const PatchArm s;
  // j2's end tag misspelt.
  std::string broken = kUrdf;
  const size_t end_tag = broken.find("</joint>", broken.find("<joint name=\"j2\""));
  broken.replace(end_tag, 8, "</jiont>");
  try {
    patchUrdfMarkers(broken, s.robot, s.sensors, s.theta, "broken.urdf");
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "broken.urdf");
    EXPECT_EQ(e.line(), 1 + std::count(broken.begin(), broken.begin() + end_tag, '\n')) << e.what();
    EXPECT_NE(std::string(e.what()).find("</jiont> closes <joint>"), std::string::npos) << e.what();
  }
  std::string unterminated = kUrdf;
  unterminated += "<!-- trailing";
  try {
    patchUrdfMarkers(unterminated, s.robot, s.sensors, s.theta, "broken.urdf");
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), static_cast<int>(lines(kUrdf).size()) + 1) << e.what();
    EXPECT_NE(std::string(e.what()).find("unterminated comment"), std::string::npos) << e.what();
  }
  // A text that is not the model's: the marker link's joint is missing.
  std::string other = kUrdf;
  const std::string joint_name = "name=\"mk_a_joint\" type";
  other.replace(other.find(joint_name), joint_name.size(), "name=\"mk_a_jnt\" type");
  try {
    patchUrdfMarkers(other, s.robot, s.sensors, s.theta, "other.urdf");
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("mk_a_joint"), std::string::npos) << e.what();
  }
  SensorParameters short_theta = s.theta;
  short_theta.marker_position.pop_back();
  EXPECT_THROW(patchUrdfMarkers(kUrdf, s.robot, s.sensors, short_theta), std::invalid_argument);
}

}  // namespace
}  // namespace stac
