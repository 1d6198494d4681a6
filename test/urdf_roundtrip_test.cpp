// Any URDF the loader accepts, the writer can patch: on every bundled and
// external robot, every joint's <origin> moved by a small correction, the
// text reloaded; the patched origins are what was asked, nothing else in
// the model moved, and the text changed only inside those <origin> tags.
// Also on random mutations of a small URDF: whatever of them loads patches.
#include <console_bridge/console.h>
#include <gtest/gtest.h>
#include <urdf_model/pose.h>

#include <Eigen/Geometry>
#include <map>
#include <optional>
#include <random>

#include "io/urdf_document.hpp"
#include "io/urdf_edit.hpp"
#include "stac/error.hpp"
#include "stac/robot_model.hpp"
#include "stac/urdf_patch.hpp"
#include "support/test_util.hpp"

namespace stac {
namespace {

std::vector<std::string> allUrdfs() {
  std::vector<std::string> out = test::externalUrdfs();
  for (const char* f : {"gimbal2.urdf", "hand24.urdf", "humanoid38.urdf"})
    out.push_back(test::dataPath(f));
  return out;
}

// An <origin> attribute as urdfdom reads it (absent: zero).
Eigen::Vector3d originValue(const io::UrdfDocument& doc, const io::UrdfJoint& j,
                            const char* key) {
  if (j.origin < 0) return Eigen::Vector3d::Zero();
  const io::XmlAttribute* a = doc.xml().elements()[j.origin].attribute(key);
  if (!a) return Eigen::Vector3d::Zero();
  urdf::Vector3 v;
  v.init(a->value);
  return {v.x, v.y, v.z};
}

// A correction per joint, different for each.
std::vector<io::OriginEdit> correctEveryJoint(const io::UrdfDocument& doc) {
  std::vector<io::OriginEdit> edits;
  int k = 0;
  for (const io::UrdfJoint& j : doc.joints()) {
    const double s = 1e-3 * (1 + k++ % 7);
    edits.push_back({j.name, originValue(doc, j, "xyz") + Eigen::Vector3d(s, -2 * s, 0.5 * s),
                     originValue(doc, j, "rpy") + Eigen::Vector3d(-s, 0.3 * s, 2 * s)});
  }
  return edits;
}

// The text with each joint's <origin> start tag reduced to "<origin>"; in
// `patched`, an <origin> the writer inserted (the joint had none in
// `original`) is dropped with the line break and indent that came with it.
std::string masked(const io::UrdfDocument& doc, const io::UrdfDocument& original) {
  std::string text = doc.text();
  const auto& el = doc.xml().elements();
  for (auto j = doc.joints().rbegin(); j != doc.joints().rend(); ++j) {
    if (j->origin < 0) continue;
    const io::XmlElement& o = el[j->origin];
    if (original.joint(j->name)->origin >= 0)
      text.replace(o.begin, o.tag_end - o.begin, "<origin>");
    else
      text.erase(el[j->element].tag_end, o.tag_end - el[j->element].tag_end);
  }
  return text;
}

// Everything but the link origins of the patched joints is unchanged.
void expectSameModelBut(const RobotModel& a, const RobotModel& b, const std::string& file) {
  ASSERT_EQ(a.numLinks(), b.numLinks()) << file;
  ASSERT_EQ(a.dof(), b.dof()) << file;
  for (int i = 0; i < a.dof(); ++i) EXPECT_EQ(a.qName(i), b.qName(i)) << file;
  EXPECT_EQ(a.lowerLimits(), b.lowerLimits()) << file;
  EXPECT_EQ(a.upperLimits(), b.upperLimits()) << file;
  EXPECT_EQ(a.allJointNames(), b.allJointNames()) << file;
  for (int l = 0; l < a.numLinks(); ++l) {
    const Link &la = a.links()[l], &lb = b.links()[l];
    EXPECT_EQ(la.name, lb.name) << file;
    EXPECT_EQ(la.parent, lb.parent) << file << " " << la.name;
    EXPECT_EQ(la.joint_name, lb.joint_name) << file << " " << la.name;
    EXPECT_EQ(la.movable_joint, lb.movable_joint) << file << " " << la.name;
    EXPECT_EQ(la.axis, lb.axis) << file << " " << la.name;
  }
  ASSERT_EQ(a.movableJoints().size(), b.movableJoints().size()) << file;
  for (size_t i = 0; i < a.movableJoints().size(); ++i) {
    const MovableJoint &ja = a.movableJoints()[i], &jb = b.movableJoints()[i];
    EXPECT_EQ(ja.name, jb.name) << file;
    EXPECT_EQ(ja.q_index, jb.q_index) << file << " " << ja.name;
    EXPECT_EQ(ja.multiplier, jb.multiplier) << file << " " << ja.name;
    EXPECT_EQ(ja.offset, jb.offset) << file << " " << ja.name;
  }
}

TEST(UrdfRoundTrip, EveryJointOriginOfEveryRobotPatches) {
  for (const std::string& file : allUrdfs()) {
    const RobotModel robot = RobotModel::fromFile(file);
    const io::UrdfDocument& doc = robot.urdfDocument();
    const std::vector<io::OriginEdit> edits = correctEveryJoint(doc);
    const std::string text = io::withJointOrigins(doc, edits);
    const RobotModel patched = RobotModel::fromString(text, file + " (patched)");
    expectSameModelBut(robot, patched, file);
    std::map<std::string, const io::OriginEdit*> edit_of;
    for (const io::OriginEdit& e : edits) edit_of[e.joint] = &e;
    int moved = 0;
    for (const Link& link : patched.links()) {
      if (link.joint_name.empty()) continue;
      const io::OriginEdit& e = *edit_of.at(link.joint_name);
      // Written with round-trip digits: read back exactly.
      EXPECT_EQ(link.origin.translation(), *e.xyz) << file << " " << link.joint_name;
      urdf::Rotation r;
      r.setFromRPY(e.rpy->x(), e.rpy->y(), e.rpy->z());
      const Eigen::Matrix3d R = Eigen::Quaterniond(r.w, r.x, r.y, r.z).normalized().toRotationMatrix();
      EXPECT_LT((link.origin.linear() - R).norm(), 1e-14) << file << " " << link.joint_name;
      ++moved;
    }
    EXPECT_EQ(moved, static_cast<int>(doc.joints().size())) << file;
    EXPECT_EQ(masked(patched.urdfDocument(), doc), masked(doc, doc)) << file;
  }
}

TEST(UrdfRoundTrip, MarkersOnEveryLeafLinkOfEveryRobotPatch) {
  for (const std::string& file : allUrdfs()) {
    const RobotModel robot = RobotModel::fromFile(file);
    std::vector<int> children(robot.numLinks(), 0);
    for (const Link& l : robot.links())
      if (l.parent >= 0) ++children[l.parent];
    SensorSet sensors;
    SensorParameters theta;
    for (int l = 0; l < robot.numLinks(); ++l) {
      const Link& link = robot.links()[l];
      if (link.parent < 0 || link.movable_joint >= 0 || children[l] > 0) continue;
      MarkerConfig m;
      m.name = "marker_" + link.name;
      m.link_name = link.name;
      m.link = l;
      sensors.markers.push_back(m);
      theta.marker_position.push_back(Eigen::Vector3d(0.01, -0.02, 0.03));
    }
    // patchUrdfMarkers checks its own result (each link on its marker).
    const UrdfPatch p = patchUrdfMarkers(robot, sensors, theta);
    EXPECT_EQ(p.placed.size(), sensors.markers.size()) << file;
    EXPECT_TRUE(p.unplaced.empty()) << file;
  }
}

// Random edits of the characters that make XML structure: whatever the
// loader still accepts, the writer patches and the loader reads back.
TEST(UrdfRoundTrip, MutantsTheLoaderAcceptsPatch) {
  const std::string base = test::readFile(test::dataPath("gimbal2.urdf"));
  const std::string alphabet = "<>/=\"' &;#x\t\n\x01!-?[]";
  std::mt19937 rng(12345);
  int accepted = 0;
  // urdfdom logs each text it rejects (a mutated number, mostly) to stderr.
  const console_bridge::LogLevel level = console_bridge::getLogLevel();
  console_bridge::setLogLevel(console_bridge::CONSOLE_BRIDGE_LOG_NONE);
  for (int trial = 0; trial < 3000; ++trial) {
    std::string text = base;
    const int n = 1 + static_cast<int>(rng() % 3);
    for (int k = 0; k < n; ++k) {
      const size_t at = rng() % text.size();
      const char c = alphabet[rng() % alphabet.size()];
      switch (rng() % 3) {
        case 0: text.insert(at, 1, c); break;
        case 1: text.erase(at, 1); break;
        default: text[at] = c;
      }
    }
    std::optional<RobotModel> robot;
    try {
      robot = RobotModel::fromString(text, "mutant.urdf");
    } catch (const InputError&) {
      continue;
    }
    ++accepted;
    const std::string patched = io::withJointOrigins(robot->urdfDocument(),
                                                     correctEveryJoint(robot->urdfDocument()));
    EXPECT_NO_THROW(RobotModel::fromString(patched, "patched.urdf")) << text;
  }
  console_bridge::setLogLevel(level);
  RecordProperty("accepted", accepted);
  EXPECT_GT(accepted, 100);
}

}  // namespace
}  // namespace stac
