#include "stac/sensor_models.hpp"

#include <algorithm>

namespace stac {

std::vector<int> supportColumns(const RobotModel& robot, int link) {
  std::vector<int> cols;
  for (int j : robot.supportingJoints(link))
    cols.push_back(robot.movableJoints()[j].q_index);
  std::sort(cols.begin(), cols.end());
  cols.erase(std::unique(cols.begin(), cols.end()), cols.end());
  return cols;
}

namespace tendon_sensor {

double length(const RobotModel& robot, const TendonSensorConfig& s,
              const KinematicsWorkspace& ws) {
  double L = 0.0;
  if (s.kind == TendonSensorConfig::Kind::kCoupling) {
    for (const CouplingTerm& c : s.coupling) L += c.coefficient * ws.movable_q[c.joint];
    return L;
  }
  (void)robot;
  Eigen::Vector3d prev = ws.link_pose[s.path[0].link] * s.path[0].point;
  for (size_t k = 1; k < s.path.size(); ++k) {
    const Eigen::Vector3d next = ws.link_pose[s.path[k].link] * s.path[k].point;
    L += (next - prev).norm();
    prev = next;
  }
  return L;
}

void addLengthJacobian(const RobotModel& robot, const TendonSensorConfig& s,
                       const KinematicsWorkspace& ws, double scale,
                       Eigen::Ref<Eigen::RowVectorXd> row) {
  if (s.kind == TendonSensorConfig::Kind::kCoupling) {
    for (const CouplingTerm& c : s.coupling) {
      const MovableJoint& mj = robot.movableJoints()[c.joint];
      row[mj.q_index] += scale * c.coefficient * mj.multiplier;
    }
    return;
  }
  for (size_t k = 0; k + 1 < s.path.size(); ++k) {
    const Eigen::Vector3d a = ws.link_pose[s.path[k].link] * s.path[k].point;
    const Eigen::Vector3d b = ws.link_pose[s.path[k + 1].link] * s.path[k + 1].point;
    const double n = (b - a).norm();
    if (n < 1e-12) continue;  // coincident anchors: L is not differentiable
    const Eigen::Vector3d u = (b - a) / n;
    addPointJacobianTransposed(robot, ws, s.path[k + 1].link, b, scale * u, row);
    addPointJacobianTransposed(robot, ws, s.path[k].link, a, -scale * u, row);
  }
}

void addOriginLengthJacobian(const TendonSensorConfig& s, const KinematicsWorkspace& ws,
                             const std::vector<int>& origins,
                             const std::vector<std::vector<int>>& anchor_slots, double scale,
                             Eigen::Ref<Eigen::RowVectorXd, 0, Eigen::InnerStride<>> row) {
  for (size_t k = 0; k + 1 < s.path.size(); ++k) {
    const Eigen::Vector3d a = ws.link_pose[s.path[k].link] * s.path[k].point;
    const Eigen::Vector3d b = ws.link_pose[s.path[k + 1].link] * s.path[k + 1].point;
    const double n = (b - a).norm();
    if (n < 1e-12) continue;  // coincident anchors: L is not differentiable
    const Eigen::RowVector3d u = (b - a).transpose() / n;
    for (int end = 0; end < 2; ++end) {
      const Eigen::Vector3d& point = end ? b : a;
      for (int slot : anchor_slots[k + end]) {
        Eigen::Matrix<double, 3, 6> J = Eigen::Matrix<double, 3, 6>::Zero();
        addOriginJacobian(ws, origins[slot], point, 1.0, J);
        row.segment<6>(6 * slot) += (end ? scale : -scale) * (u * J);
      }
    }
  }
}

std::vector<int> columns(const RobotModel& robot, const TendonSensorConfig& s) {
  std::vector<int> cols;
  if (s.kind == TendonSensorConfig::Kind::kCoupling) {
    for (const CouplingTerm& c : s.coupling)
      cols.push_back(robot.movableJoints()[c.joint].q_index);
  } else {
    for (const PathAnchor& a : s.path) {
      const std::vector<int> c = supportColumns(robot, a.link);
      cols.insert(cols.end(), c.begin(), c.end());
    }
  }
  std::sort(cols.begin(), cols.end());
  cols.erase(std::unique(cols.begin(), cols.end()), cols.end());
  return cols;
}

}  // namespace tendon_sensor

namespace marker_sensor {

Eigen::Matrix3d rotationJacobian(const Eigen::Matrix3d& R,
                                 const Eigen::Vector3d& x_base) {
  const Eigen::Vector3d y = R * x_base;
  Eigen::Matrix3d S;
  S << 0, y.z(), -y.y(), -y.z(), 0, y.x(), y.y(), -y.x(), 0;  // -[y]x
  return S;
}

std::vector<int> columns(const RobotModel& robot, int link) {
  return supportColumns(robot, link);
}

}  // namespace marker_sensor
}  // namespace stac
