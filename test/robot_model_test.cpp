// RobotModel and kinematics: closed forms, finite differences, KDL's own
// solvers, mimic equivalence, and every bad-URDF message.
#include <gtest/gtest.h>

#include <cmath>
#include <kdl/treefksolverpos_recursive.hpp>
#include <random>
#include <string>

#include "stac/error.hpp"
#include "stac/kinematics.hpp"
#include "stac/robot_model.hpp"
#include "support/test_util.hpp"

namespace stac {
namespace {

const char* kPlanar2 = R"(<?xml version="1.0"?>
<robot name="planar2">
  <link name="base"/>
  <link name="upper"/>
  <link name="fore"/>
  <link name="tip"/>
  <joint name="shoulder" type="revolute">
    <parent link="base"/><child link="upper"/>
    <origin xyz="0 0 0.1"/><axis xyz="0 0 1"/>
    <limit lower="-3" upper="3" effort="1" velocity="1"/>
  </joint>
  <joint name="elbow" type="revolute">
    <parent link="upper"/><child link="fore"/>
    <origin xyz="0.5 0 0"/><axis xyz="0 0 1"/>
    <limit lower="-3" upper="3" effort="1" velocity="1"/>
  </joint>
  <joint name="tip_joint" type="fixed">
    <parent link="fore"/><child link="tip"/><origin xyz="0.3 0 0"/>
  </joint>
</robot>)";

TEST(RobotModel, PlanarArmMatchesClosedForm) {
  RobotModel m = RobotModel::fromString(kPlanar2);
  ASSERT_EQ(m.dof(), 2);
  EXPECT_EQ(m.qName(0), "shoulder");
  EXPECT_EQ(m.qName(1), "elbow");
  KinematicsWorkspace ws(m);
  std::mt19937 rng(1);
  for (int k = 0; k < 20; ++k) {
    Eigen::VectorXd q = test::randomQ(m, rng);
    forwardKinematics(m, q, &ws);
    const double a = q[0], b = q[0] + q[1];
    Eigen::Vector3d tip(0.5 * std::cos(a) + 0.3 * std::cos(b),
                        0.5 * std::sin(a) + 0.3 * std::sin(b), 0.1);
    const int t = *m.linkIndex("tip");
    EXPECT_LT((ws.link_pose[t].translation() - tip).norm(), 1e-12);
    Eigen::MatrixXd J(3, 2);
    pointJacobian(m, ws, t, tip, J);
    Eigen::MatrixXd Jc(3, 2);
    Jc << -0.5 * std::sin(a) - 0.3 * std::sin(b), -0.3 * std::sin(b),
        0.5 * std::cos(a) + 0.3 * std::cos(b), 0.3 * std::cos(b), 0, 0;
    EXPECT_LT((J - Jc).norm(), 1e-12);
  }
}

std::vector<std::string> allUrdfs() {
  std::vector<std::string> files;
  for (const char* n : {"gimbal2.urdf", "hand24.urdf", "humanoid38.urdf"}) {
    const std::string p = test::dataPath(n);
    if (!test::readFile(p).empty()) files.push_back(p);
  }
  for (const std::string& p : test::externalUrdfs()) files.push_back(p);
  return files;
}

// Relative error of every point Jacobian against central differences.
void checkJacobians(const RobotModel& m, int trials) {
  KinematicsWorkspace ws(m), ws2(m);
  std::mt19937 rng(7);
  const double h = 1e-6;
  for (int k = 0; k < trials; ++k) {
    const Eigen::VectorXd q = test::randomQ(m, rng);
    forwardKinematics(m, q, &ws);
    for (int l = 0; l < m.numLinks(); ++l) {
      const Eigen::Vector3d d = Eigen::Vector3d::Random() * 0.05;
      const Eigen::Vector3d p = ws.link_pose[l] * d;
      Eigen::MatrixXd J(3, m.dof()), Jfd(3, m.dof());
      pointJacobian(m, ws, l, p, J);
      for (int i = 0; i < m.dof(); ++i) {
        Eigen::VectorXd qp = q, qm = q;
        qp[i] += h;
        qm[i] -= h;
        forwardKinematics(m, qp, &ws2);
        const Eigen::Vector3d pp = ws2.link_pose[l] * d;
        forwardKinematics(m, qm, &ws2);
        const Eigen::Vector3d pm = ws2.link_pose[l] * d;
        Jfd.col(i) = (pp - pm) / (2 * h);
      }
      const double scale = std::max(Jfd.norm(), 1e-3);
      ASSERT_LT((J - Jfd).norm() / scale, 1e-6)
          << m.sourceName() << " link " << m.links()[l].name;
    }
  }
}

TEST(RobotModel, LinkOfJointNamesTheLinkAJointAttaches) {
  const RobotModel m = RobotModel::fromString(kPlanar2);
  EXPECT_EQ(m.linkOfJoint("elbow"), m.linkIndex("fore"));
  EXPECT_EQ(m.linkOfJoint("tip_joint"), m.linkIndex("tip"));  // a fixed joint too
  EXPECT_FALSE(m.linkOfJoint("upper"));  // a link's name is not a joint's
  EXPECT_FALSE(m.linkOfJoint(""));       // the root has no joint
}

// A <limit> with effort and velocity only reads as lower = upper = 0 (the
// URDF default): limits that span nothing bound nothing, and the revolute
// joint turns freely, as MuJoCo's importer reads it (an unseen quadruped's
// knees); so does one whose lower lies above its upper.
TEST(RobotModel, LimitsThatSpanNothingMakeARevoluteJointContinuous) {
  std::string urdf = kPlanar2;
  const std::string limits = R"(<limit lower="-3" upper="3" effort="1" velocity="1"/>)";
  urdf.replace(urdf.find(limits), limits.size(), R"(<limit effort="1" velocity="1"/>)");
  urdf.replace(urdf.find(limits), limits.size(), R"(<limit lower="1" upper="-1" effort="1" velocity="1"/>)");
  const RobotModel m = RobotModel::fromString(urdf);
  for (int j = 0; j < 2; ++j) {
    EXPECT_FALSE(std::isfinite(m.lowerLimits()[j])) << j;
    EXPECT_FALSE(std::isfinite(m.upperLimits()[j])) << j;
    EXPECT_EQ(m.movableJoints()[m.qJoints()[j]].type, JointType::kContinuous) << j;
  }
  const RobotModel limited = RobotModel::fromString(kPlanar2);  // the same with limits
  EXPECT_EQ(limited.lowerLimits()[1], -3);
  EXPECT_EQ(limited.movableJoints()[limited.qJoints()[1]].type, JointType::kRevolute);
}

TEST(RobotModel, PointJacobiansMatchFiniteDifferencesOnEveryRobot) {
  const auto files = allUrdfs();
  ASSERT_FALSE(files.empty());
  for (const std::string& f : files) {
    SCOPED_TRACE(f);
    checkJacobians(RobotModel::fromFile(f), 3);
  }
}

TEST(RobotModel, ForwardKinematicsMatchesKdlTreeSolver) {
  for (const std::string& f : allUrdfs()) {
    SCOPED_TRACE(f);
    RobotModel m = RobotModel::fromFile(f);
    KDL::TreeFkSolverPos_recursive fk(m.kdlTree());
    KinematicsWorkspace ws(m);
    std::mt19937 rng(3);
    const Eigen::VectorXd q = test::randomQ(m, rng);
    forwardKinematics(m, q, &ws);
    KDL::JntArray kq(m.kdlTree().getNrOfJoints());
    for (size_t j = 0; j < m.movableJoints().size(); ++j)
      kq(m.kdlJointIndex()[j]) = ws.movable_q[j];
    for (int l = 1; l < m.numLinks(); ++l) {
      KDL::Frame F;
      ASSERT_GE(fk.JntToCart(kq, F, m.links()[l].name), 0);
      Eigen::Vector3d p(F.p.x(), F.p.y(), F.p.z());
      EXPECT_LT((p - ws.link_pose[l].translation()).norm(), 1e-9)
          << m.links()[l].name;
      Eigen::Matrix3d R;
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) R(r, c) = F.M(r, c);
      EXPECT_LT((R - ws.link_pose[l].linear()).norm(), 1e-9);
    }
  }
}

TEST(RobotModel, ExternalRobotsHaveTheExpectedJointVector) {
  for (const std::string& f : test::externalUrdfs()) {
    RobotModel m = RobotModel::fromFile(f);
    if (f.find("ur5") != std::string::npos) {
      EXPECT_EQ(m.dof(), 6);
      EXPECT_EQ(m.qName(0), "shoulder_pan_joint");
    } else if (f.find("panda") != std::string::npos) {
      EXPECT_EQ(m.dof(), 8);
      const auto& mj = m.movableJoints()[*m.movableJointIndex("panda_finger_joint2")];
      EXPECT_TRUE(mj.is_mimic);
      EXPECT_EQ(mj.q_index, *m.qIndex("panda_finger_joint1"));
      EXPECT_DOUBLE_EQ(mj.multiplier, 1.0);
    } else if (f.find("talos") != std::string::npos) {
      EXPECT_EQ(m.dof(), 32);
      EXPECT_EQ(m.movableJoints().size(), 44u);
    }
  }
}

const char* kMimic = R"(<robot name="mimic">
  <link name="base"/><link name="a"/><link name="b"/><link name="c"/>
  <joint name="j1" type="revolute"><parent link="base"/><child link="a"/>
    <origin xyz="0 0 0.2" rpy="0.1 0 0"/><axis xyz="0 1 0"/>
    <limit lower="-2" upper="2" effort="1" velocity="1"/></joint>
  <joint name="j2" type="revolute"><parent link="a"/><child link="b"/>
    <origin xyz="0.3 0 0"/><axis xyz="1 0 1"/>
    <limit lower="-2" upper="2" effort="1" velocity="1"/>
    %MIMIC%</joint>
  <joint name="j3" type="prismatic"><parent link="b"/><child link="c"/>
    <origin xyz="0.1 0.1 0"/><axis xyz="0 0 1"/>
    <limit lower="-0.1" upper="0.1" effort="1" velocity="1"/>
    %MIMIC3%</joint>
</robot>)";

std::string replaceAll(std::string s, const std::string& from, const std::string& to) {
  for (size_t p = s.find(from); p != std::string::npos; p = s.find(from, p + to.size()))
    s.replace(p, from.size(), to);
  return s;
}

TEST(RobotModel, MimicFollowersMatchHandSetIndependentJoints) {
  // j2 = -0.7 j1 + 0.2; j3 (follower of a follower) = 0.05 j2 - 0.01.
  RobotModel mim = RobotModel::fromString(replaceAll(
      replaceAll(kMimic, "%MIMIC%", R"(<mimic joint="j1" multiplier="-0.7" offset="0.2"/>)"),
      "%MIMIC3%", R"(<mimic joint="j2" multiplier="0.05" offset="-0.01"/>)"));
  RobotModel ind = RobotModel::fromString(
      replaceAll(replaceAll(kMimic, "%MIMIC%", ""), "%MIMIC3%", ""));
  ASSERT_EQ(mim.dof(), 1);
  ASSERT_EQ(ind.dof(), 3);
  KinematicsWorkspace wm(mim), wi(ind);
  for (double t : {-1.0, 0.3, 1.2}) {
    Eigen::VectorXd q(1), qi(3);
    q << t;
    const double j2 = -0.7 * t + 0.2;
    qi << t, j2, 0.05 * j2 - 0.01;
    forwardKinematics(mim, q, &wm);
    forwardKinematics(ind, qi, &wi);
    const int c = *mim.linkIndex("c");
    const Eigen::Vector3d p = wm.link_pose[c] * Eigen::Vector3d(0.01, 0.02, 0.03);
    EXPECT_LT((wm.link_pose[c].matrix() - wi.link_pose[c].matrix()).norm(), 1e-12);
    Eigen::MatrixXd Jm(3, 1), Ji(3, 3);
    pointJacobian(mim, wm, c, p, Jm);
    pointJacobian(ind, wi, c, p, Ji);
    // Chain rule: dp/dt = Ji0 + Ji1 * (-0.7) + Ji2 * 0.05 * (-0.7).
    const Eigen::Vector3d expect = Ji.col(0) - 0.7 * Ji.col(1) - 0.035 * Ji.col(2);
    EXPECT_LT((Jm.col(0) - expect).norm(), 1e-12);
  }
}

void expectError(const std::string& urdf, const std::string& needle, int line) {
  try {
    RobotModel::fromString(urdf, "bad.urdf");
    FAIL() << "no error for " << needle;
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.urdf"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    if (line > 0) {
      EXPECT_EQ(e.line(), line) << e.what();
    }
  }
}

TEST(RobotModelErrors, MalformedXml) {
  expectError("<robot name='x'>\n<link name='a'>\n</robot>", "malformed XML", 0);
}

TEST(RobotModelErrors, MissingFile) {
  try {
    RobotModel::fromFile("/nonexistent/robot.urdf");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/robot.urdf"), std::string::npos);
  }
}

TEST(RobotModelErrors, UnknownLink) {
  expectError(
      "<robot name='x'>\n<link name='a'/>\n<joint name='j' type='fixed'>\n"
      "<parent link='a'/><child link='ghost'/></joint>\n</robot>",
      "unknown link 'ghost'", 3);
}

TEST(RobotModelErrors, FloatingJoint) {
  expectError(
      "<robot name='x'>\n<link name='a'/><link name='b'/>\n"
      "<joint name='free' type='floating'>\n<parent link='a'/><child link='b'/>"
      "</joint>\n</robot>",
      "floating", 3);
}

TEST(RobotModelErrors, PlanarJoint) {
  expectError(
      "<robot name='x'>\n<link name='a'/><link name='b'/>\n"
      "<joint name='p' type='planar'>\n<parent link='a'/><child link='b'/>"
      "</joint>\n</robot>",
      "planar", 3);
}

TEST(RobotModelErrors, EmptyRobot) {
  expectError("<robot name='x'>\n</robot>", "empty robot", 1);
}

TEST(RobotModelErrors, MimicOfUnknownJoint) {
  expectError(
      "<robot name='x'>\n<link name='a'/><link name='b'/>\n"
      "<joint name='j' type='revolute'><parent link='a'/><child link='b'/>"
      "<limit lower='-1' upper='1' effort='1' velocity='1'/>"
      "<mimic joint='nope'/></joint>\n</robot>",
      "mimics unknown joint 'nope'", 3);
}

TEST(RobotModelErrors, NotARobot) {
  expectError("<model/>", "root element must be <robot>", 0);
}

}  // namespace
}  // namespace stac
