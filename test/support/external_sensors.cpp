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

}  // namespace stac::test
