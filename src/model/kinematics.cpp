#include "stac/kinematics.hpp"

#include <cassert>

namespace stac {

KinematicsWorkspace::KinematicsWorkspace(const RobotModel& model)
    : movable_q(Eigen::VectorXd::Zero(model.movableJoints().size())),
      link_pose(model.numLinks(), Eigen::Isometry3d::Identity()),
      joint_axis(model.movableJoints().size(), Eigen::Vector3d::UnitZ()),
      joint_origin(model.movableJoints().size(), Eigen::Vector3d::Zero()) {}

void forwardKinematics(const RobotModel& model, const Eigen::VectorXd& q,
                       KinematicsWorkspace* ws) {
  assert(q.size() == model.dof());
  model.expand(q, &ws->movable_q);
  const std::vector<Link>& links = model.links();
  const std::vector<MovableJoint>& joints = model.movableJoints();
  // Links are stored parent-before-child, so one forward sweep suffices.
  for (size_t i = 0; i < links.size(); ++i) {
    const Link& link = links[i];
    if (link.parent < 0) {
      ws->link_pose[i].setIdentity();
      continue;
    }
    Eigen::Isometry3d& T = ws->link_pose[i];
    T = ws->link_pose[link.parent] * link.origin;
    if (link.movable_joint < 0) continue;
    const int j = link.movable_joint;
    const double angle = ws->movable_q[j];
    const Eigen::Vector3d axis_base = T.linear() * link.axis;
    ws->joint_axis[j] = axis_base;
    ws->joint_origin[j] = T.translation();
    if (joints[j].type == JointType::kPrismatic) {
      T.translation() += angle * axis_base;
    } else {
      T.linear() = T.linear() * Eigen::AngleAxisd(angle, link.axis).toRotationMatrix();
    }
  }
}

void pointJacobian(const RobotModel& model, const KinematicsWorkspace& ws,
                   int link, const Eigen::Vector3d& point_in_base,
                   Eigen::Ref<Eigen::MatrixXd> J) {
  assert(J.rows() == 3 && J.cols() == model.dof());
  J.setZero();
  addPointJacobian(model, ws, link, point_in_base, nullptr, J);
}

void addPointJacobian(const RobotModel& model, const KinematicsWorkspace& ws, int link,
                      const Eigen::Vector3d& point_in_base, const int* slots,
                      Eigen::Ref<Eigen::MatrixXd> J) {
  const std::vector<MovableJoint>& joints = model.movableJoints();
  const std::vector<int>& support = model.supportingJoints(link);
  for (size_t i = 0; i < support.size(); ++i) {
    const int j = support[i];
    const MovableJoint& mj = joints[j];
    const int c = slots ? slots[i] : mj.q_index;
    if (mj.type == JointType::kPrismatic) {
      J.col(c) += mj.multiplier * ws.joint_axis[j];
    } else {
      J.col(c) += mj.multiplier * ws.joint_axis[j].cross(point_in_base - ws.joint_origin[j]);
    }
  }
}

void addPointJacobianTransposed(const RobotModel& model,
                                const KinematicsWorkspace& ws, int link,
                                const Eigen::Vector3d& point_in_base,
                                const Eigen::Vector3d& w,
                                Eigen::Ref<Eigen::RowVectorXd> row) {
  const std::vector<MovableJoint>& joints = model.movableJoints();
  for (int j : model.supportingJoints(link)) {
    const MovableJoint& mj = joints[j];
    const Eigen::Vector3d col =
        mj.type == JointType::kPrismatic
            ? ws.joint_axis[j]
            : Eigen::Vector3d(ws.joint_axis[j].cross(point_in_base - ws.joint_origin[j]));
    row[mj.q_index] += mj.multiplier * w.dot(col);
  }
}

}  // namespace stac
