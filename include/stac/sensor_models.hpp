// The three sensor types' forward maps and Jacobians (SPEC §1), one section
// per type. The residual assembly (measurement.hpp), the θ-phase updates
// (theta_phase.hpp) and the monolithic Ceres problem all call these, so each
// type's maths lives here once.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

#include "stac/kinematics.hpp"
#include "stac/robot_model.hpp"
#include "stac/sensors.hpp"

namespace stac {

// ---- Joint sensor: p = gain * a + bias, a = multiplier * q[i] + offset ----
namespace joint_sensor {
// The sensed joint's angle (mimic followers via their master).
inline double angle(const RobotModel& robot, const JointSensorConfig& s,
                    const Eigen::VectorXd& q) {
  const MovableJoint& mj = robot.movableJoints()[s.joint];
  return mj.multiplier * q[mj.q_index] + mj.offset;
}
// d angle / d q[column()] (the only nonzero entry).
inline double angleDerivative(const RobotModel& robot, const JointSensorConfig& s) {
  return robot.movableJoints()[s.joint].multiplier;
}
inline int column(const RobotModel& robot, const JointSensorConfig& s) {
  return robot.movableJoints()[s.joint].q_index;
}
}  // namespace joint_sensor

// ---- Tendon sensor: p = gain * L(q) + bias ----
namespace tendon_sensor {
// L(q) from the current kinematics (path) or from q (coupling).
double length(const RobotModel& robot, const TendonSensorConfig& s,
              const KinematicsWorkspace& ws);
// Adds dL/dq into row (1 x dof): for a path, Σ_k u_k^T (J_{k+1} - J_k) with
// u_k the unit vector from anchor k to k+1; for a coupling, Σ c_j da_j/dq.
void addLengthJacobian(const RobotModel& robot, const TendonSensorConfig& s,
                       const KinematicsWorkspace& ws, double scale,
                       Eigen::Ref<Eigen::RowVectorXd> row);
// The q columns L can depend on, sorted.
std::vector<int> columns(const RobotModel& robot, const TendonSensorConfig& s);
// dL/d(joint-origin corrections) of a path, times scale, added into row
// (1 x 6·origins.size(), the corrections `origins` in that order):
// Σ_k u_kᵀ (da_{k+1}/dc - da_k/dc), anchor k moved by the corrections at
// the positions anchor_slots[k] of `origins` (kinematics.hpp addOriginJacobian).
void addOriginLengthJacobian(const TendonSensorConfig& s, const KinematicsWorkspace& ws,
                             const std::vector<int>& origins,
                             const std::vector<std::vector<int>>& anchor_slots, double scale,
                             Eigen::Ref<Eigen::RowVectorXd, 0, Eigen::InnerStride<>> row);
}  // namespace tendon_sensor

// ---- Marker: x = R (h_k(q) d) + t ----
namespace marker_sensor {
// Marker position in the base frame: h_k(q) d.
inline Eigen::Vector3d positionInBase(const KinematicsWorkspace& ws, int link,
                                      const Eigen::Vector3d& d) {
  return ws.link_pose[link] * d;
}
// Predicted mocap reading.
inline Eigen::Vector3d predict(const Eigen::Matrix3d& R, const Eigen::Vector3d& t,
                               const Eigen::Vector3d& x_base) {
  return R * x_base + t;
}
// dx/d(rotation) for the left perturbation R <- exp([δ]x) R: -[R x_base]x.
Eigen::Matrix3d rotationJacobian(const Eigen::Matrix3d& R,
                                 const Eigen::Vector3d& x_base);
// q columns of a marker on `link`, sorted.
std::vector<int> columns(const RobotModel& robot, int link);
}  // namespace marker_sensor

// Sorted unique q columns of the joints supporting a link.
std::vector<int> supportColumns(const RobotModel& robot, int link);

}  // namespace stac
