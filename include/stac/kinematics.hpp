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

#include "stac/joint_origins.hpp"
#include "stac/robot_model.hpp"

namespace stac {

struct KinematicsWorkspace {
  explicit KinematicsWorkspace(const RobotModel& model);

  Eigen::VectorXd movable_q;                     // full joint vector
  std::vector<Eigen::Isometry3d> link_pose;      // link frame in base frame
  std::vector<Eigen::Vector3d> joint_axis;       // movable joint axis, base
  std::vector<Eigen::Vector3d> joint_origin;     // a point on that axis, base

  // Joint-origin corrections (joint_origins.hpp), set by
  // setOriginCorrections(): each link's origin as the sweep uses it (the
  // URDF's, or T(urdf) · T(correction)), which correction a link carries
  // (-1: none), and per correction what its Jacobian needs from the sweep:
  // the world rotation of the frame the URDF origin places, the world
  // corrected frame origin, and the world ω of its roll, pitch, yaw.
  std::vector<Eigen::Isometry3d> link_origin;
  std::vector<int> correction_of_link;
  std::vector<Eigen::Matrix3d> origin_frame, origin_rpy_axes, origin_rpy_local;
  std::vector<Eigen::Vector3d> origin_point;
  std::vector<double> applied;  // the corrections last set (xyz, rpy per joint)
};

// Applies corrections[i] to the origin of links[i] for every following
// forwardKinematics() on ws (empty: the URDF as is). Cheap when they have
// not changed since the last call.
void setOriginCorrections(const RobotModel& model, const std::vector<int>& links,
                          const std::vector<OriginCorrection>& corrections,
                          KinematicsWorkspace* ws);

// The corrections (indices into the last setOriginCorrections() lists)
// whose link lies on `link`'s path to the root, root first: the only ones
// that move a point fixed on `link`.
std::vector<int> supportingCorrections(const RobotModel& model, const std::vector<int>& links,
                                       int link);

// d(point)/d(correction c) = [d/dxyz (3) | d/drpy (3)] for a point fixed on
// a link downstream of correction c, in the base frame, added into the 3 x 6
// block J (a point's columns for that correction).
void addOriginJacobian(const KinematicsWorkspace& ws, int c, const Eigen::Vector3d& point_in_base,
                       double weight, Eigen::Ref<Eigen::Matrix<double, 3, 6>> J);

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
