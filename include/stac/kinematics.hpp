// Forward kinematics and point Jacobians for one q, in one pass over the tree.
//
// The RobotModel is immutable and shared; every thread owns a
// KinematicsWorkspace that the algorithms write into (Pinocchio's Model/Data
// split). forwardKinematics() computes the pose of every link, and the world
// axis and origin of every movable joint, in a single sweep in topological
// order; pointJacobian() then assembles the 3 x dof Jacobian of any point
// fixed on a link from those axes (no extra FK), with the mimic chain rule.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

#include "stac/robot_model.hpp"

namespace stac {

struct KinematicsWorkspace {
  explicit KinematicsWorkspace(const RobotModel& model);

  Eigen::VectorXd movable_q;                     // full joint vector
  std::vector<Eigen::Isometry3d> link_pose;      // link frame in base frame
  std::vector<Eigen::Vector3d> joint_axis;       // movable joint axis, base
  std::vector<Eigen::Vector3d> joint_origin;     // a point on that axis, base
};

// Fills ws->link_pose, joint_axis and joint_origin for q (size model.dof()).
void forwardKinematics(const RobotModel& model, const Eigen::VectorXd& q,
                       KinematicsWorkspace* ws);

// d(point)/dq for a point fixed on `link`, given in the base frame at the
// current configuration. J must be 3 x dof; it is overwritten.
void pointJacobian(const RobotModel& model, const KinematicsWorkspace& ws,
                   int link, const Eigen::Vector3d& point_in_base,
                   Eigen::Ref<Eigen::MatrixXd> J);

// Adds the same columns into J without zeroing it: supporting joint i of
// `link` (RobotModel::supportingJoints order) goes to column slots[i], e.g.
// a reading's own compact columns; with slots null, to its q index.
void addPointJacobian(const RobotModel& model, const KinematicsWorkspace& ws, int link,
                      const Eigen::Vector3d& point_in_base, const int* slots,
                      Eigen::Ref<Eigen::MatrixXd> J);

// Same, but adds `weight * w^T d(point)/dq` into a row vector (1 x dof):
// what a scalar sensor that depends on a point (a tendon anchor) needs.
void addPointJacobianTransposed(const RobotModel& model,
                                const KinematicsWorkspace& ws, int link,
                                const Eigen::Vector3d& point_in_base,
                                const Eigen::Vector3d& w,
                                Eigen::Ref<Eigen::RowVectorXd> row);

}  // namespace stac
