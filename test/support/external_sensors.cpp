#include "support/external_sensors.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cstdio>
#include <sstream>
#include <vector>

namespace stac::test {

namespace {

double uni(std::mt19937_64& rng, double a, double b) {
  return a + (b - a) * std::uniform_real_distribution<double>(0.0, 1.0)(rng);
}

std::string num(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  std::string s = buf;
  if (s.find_first_of(".e") == std::string::npos) s += ".0";
  if (s.find('e') != std::string::npos && s.find('.') == std::string::npos)
    s.insert(s.find('e'), ".0");
  return s;
}

}  // namespace

std::string inferableTruthYaml(const RobotModel& robot, bool fix_gauges, std::mt19937_64& rng) {
  // Links carrying markers: the root and each q joint's child link.
  std::vector<int> marker_links = {0};
  for (int i = 0; i < robot.dof(); ++i)
    marker_links.push_back(robot.movableJoints()[robot.qJoints()[i]].child_link);
  // A link is a leaf of q when no q joint's child link has it as ancestor.
  auto isLeaf = [&](int link) {
    for (int i = 0; i < robot.dof(); ++i) {
      int l = robot.links()[robot.movableJoints()[robot.qJoints()[i]].child_link].parent;
      for (; l >= 0; l = robot.links()[l].parent)
        if (l == link) return false;
    }
    return true;
  };
  std::ostringstream o;
  const Eigen::Quaterniond r =
      Eigen::Quaterniond(uni(rng, -1, 1), uni(rng, -1, 1), uni(rng, -1, 1), uni(rng, -1, 1))
          .normalized();
  o << "mocap:\n  sigma: 0.002\n  frame:\n    translation: [" << num(uni(rng, -2, 2)) << ", "
    << num(uni(rng, -2, 2)) << ", " << num(uni(rng, 0, 2)) << "]\n    quaternion: [" << num(r.w())
    << ", " << num(r.x()) << ", " << num(r.y()) << ", " << num(r.z()) << "]\n  markers:\n";
  for (size_t k = 0; k < marker_links.size(); ++k) {
    const std::string& name = robot.links()[marker_links[k]].name;
    const bool fixed = fix_gauges && (k == 0 || isLeaf(marker_links[k]));
    o << "    - name: " << name << "\n      link: " << name << "\n      position: ["
      << num(uni(rng, -0.05, 0.05)) << ", " << num(uni(rng, -0.05, 0.05)) << ", "
      << num(uni(rng, -0.05, 0.05)) << "]\n      fixed: " << (fixed ? "true" : "false") << "\n";
  }
  o << "joint_sensors:\n";
  for (int i = 0; i < robot.dof(); ++i) {
    double gain = (uni(rng, 0, 1) < 0.5 ? -1 : 1) * uni(rng, 0.5, 3.0);
    // A linear pot's gain in volts per metre: 0.5-3 V over the stroke.
    const MovableJoint& mj = robot.movableJoints()[robot.qJoints()[i]];
    if (mj.type == JointType::kPrismatic && mj.has_limits && mj.upper > mj.lower)
      gain /= std::min(1.0, mj.upper - mj.lower);
    o << "  - name: " << robot.qName(i) << "\n    joint: " << robot.qName(i)
      << "\n    gain: " << num(gain) << "\n    bias: " << num(gain * uni(rng, -1, 1))
      << "\n    sigma: 0.01\n";
  }
  return o.str();
}

namespace {

// A point r metres from the origin, in a uniformly random direction.
std::string offsetPoint(std::mt19937_64& rng, double r) {
  Eigen::Vector3d d;
  do d = Eigen::Vector3d(uni(rng, -1, 1), uni(rng, -1, 1), uni(rng, -1, 1));
  while (d.norm() > 1 || d.norm() < 1e-3);
  d *= r / d.norm();
  return "[" + num(d.x()) + ", " + num(d.y()) + ", " + num(d.z()) + "]";
}

// The rigid groups of the robot's links: each link's group is named by its
// head, the nearest link at or above it that a movable joint moves (or the
// root), since fixed joints fold a link into its parent.
struct RigidGroups {
  std::vector<int> head_of;               // per link
  std::vector<std::vector<int>> members;  // per head link: the group's links
  std::vector<int> heads;                 // every head, root first
};

RigidGroups rigidGroups(const RobotModel& robot) {
  RigidGroups g;
  g.head_of.resize(robot.numLinks());
  g.members.resize(robot.numLinks());
  for (int l = 0; l < robot.numLinks(); ++l) {
    int h = l;
    while (robot.links()[h].movable_joint < 0 && robot.links()[h].parent >= 0)
      h = robot.links()[h].parent;
    g.head_of[l] = h;
    g.members[h].push_back(l);
  }
  for (int l = 0; l < robot.numLinks(); ++l)
    if (!g.members[l].empty()) g.heads.push_back(l);
  return g;
}

int pick(std::mt19937_64& rng, const std::vector<int>& from) {
  return from[std::uniform_int_distribution<size_t>(0, from.size() - 1)(rng)];
}

}  // namespace

std::string randomLayoutTruthYaml(const RobotModel& robot, std::mt19937_64& rng) {
  const RigidGroups g = rigidGroups(robot);
  std::ostringstream o;
  o << "mocap:\n  sigma: 0.002\n  markers:\n";
  const int n = std::max(3, static_cast<int>(std::lround(uni(rng, 0.5, 1.0) * g.heads.size())));
  const int fixed_a = std::uniform_int_distribution<int>(0, n - 1)(rng);
  const int fixed_b = (fixed_a + 1 + std::uniform_int_distribution<int>(0, n - 2)(rng)) % n;
  for (int k = 0; k < n; ++k) {
    const int link = pick(rng, g.members[pick(rng, g.heads)]);
    o << "    - name: m" << k << "\n      link: " << robot.links()[link].name
      << "\n      position: " << offsetPoint(rng, uni(rng, 0.01, 0.05))
      << "\n      fixed: " << (k == fixed_a || k == fixed_b ? "true" : "false") << "\n";
  }
  o << "joint_sensors:\n";
  for (int i = 0; i < robot.dof(); ++i)
    o << "  - {name: " << robot.qName(i) << ", joint: " << robot.qName(i)
      << ", gain: 1.0, bias: 0.0, sigma: 0.01}\n";
  std::vector<int> moving;  // heads a movable joint moves
  for (int h : g.heads)
    if (robot.links()[h].movable_joint >= 0) moving.push_back(h);
  if (moving.empty()) return o.str();
  o << "tendon_sensors:\n";
  for (int k = 0; k < 3; ++k) {
    const int distal = pick(rng, moving);
    int proximal = distal;
    for (int up = std::uniform_int_distribution<int>(1, 3)(rng);
         up > 0 && robot.links()[proximal].parent >= 0; --up)
      proximal = g.head_of[robot.links()[proximal].parent];
    o << "  - name: tendon" << k << "\n    gain: 1.0\n    bias: 0.0\n    sigma: 0.001\n"
      << "    path:\n";
    for (int head : {proximal, distal})
      o << "      - {link: " << robot.links()[pick(rng, g.members[head])].name
        << ", point: " << offsetPoint(rng, uni(rng, 0.02, 0.05)) << "}\n";
  }
  return o.str();
}

}  // namespace stac::test
