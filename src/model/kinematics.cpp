#include "stac/kinematics.hpp"

#include <algorithm>
#include <cassert>

namespace stac {

KinematicsWorkspace::KinematicsWorkspace(const RobotModel& model)
    : movable_q(Eigen::VectorXd::Zero(model.movableJoints().size())),
      link_pose(model.numLinks(), Eigen::Isometry3d::Identity()),
      joint_axis(model.movableJoints().size(), Eigen::Vector3d::UnitZ()),
      joint_origin(model.movableJoints().size(), Eigen::Vector3d::Zero()),
      correction_of_link(model.numLinks(), -1) {
  for (const Link& link : model.links()) link_origin.push_back(link.origin);
}

void setOriginCorrections(const RobotModel& model, const std::vector<int>& links,
                          const std::vector<OriginCorrection>& corrections,
                          KinematicsWorkspace* ws) {
  assert(links.size() == corrections.size());
  const size_t n = corrections.size();
  bool same = ws->applied.size() == 6 * n;
  for (size_t c = 0; same && c < n; ++c)
    for (int i = 0; i < 3; ++i)
      same = same && ws->applied[6 * c + i] == corrections[c].xyz[i] &&
             ws->applied[6 * c + 3 + i] == corrections[c].rpy[i];
  if (same) return;
  for (int l = 0; l < model.numLinks(); ++l)  // undo the previous set
    if (ws->correction_of_link[l] >= 0) ws->link_origin[l] = model.links()[l].origin;
  std::fill(ws->correction_of_link.begin(), ws->correction_of_link.end(), -1);
  ws->applied.resize(6 * n);
  ws->origin_frame.resize(n);
  ws->origin_rpy_axes.resize(n);
  ws->origin_rpy_local.resize(n);
  ws->origin_point.resize(n);
  for (size_t c = 0; c < n; ++c) {
    const int link = links[c];
    ws->correction_of_link[link] = static_cast<int>(c);
    ws->link_origin[link] = model.links()[link].origin * corrections[c].transform();
    ws->origin_rpy_local[c] = corrections[c].rpyAxes();
    for (int i = 0; i < 3; ++i) {
      ws->applied[6 * c + i] = corrections[c].xyz[i];
      ws->applied[6 * c + 3 + i] = corrections[c].rpy[i];
    }
  }
}

std::vector<int> supportingCorrections(const RobotModel& model, const std::vector<int>& links,
                                       int link) {
  std::vector<int> out;
  for (int l = link; l >= 0; l = model.links()[l].parent) {
    const auto it = std::find(links.begin(), links.end(), l);
    if (it != links.end()) out.push_back(static_cast<int>(it - links.begin()));
  }
  std::reverse(out.begin(), out.end());
  return out;
}

void addOriginJacobian(const KinematicsWorkspace& ws, int c, const Eigen::Vector3d& point_in_base,
                       double weight, Eigen::Ref<Eigen::Matrix<double, 3, 6>> J) {
  // p = A (R(rpy) p_c + xyz): dp/dxyz = A's rotation; dp/drpy_k = (A ω_k) ×
  // (p - o), o the corrected frame's origin (joint_origins.hpp).
  J.leftCols<3>() += weight * ws.origin_frame[c];
  const Eigen::Vector3d arm = point_in_base - ws.origin_point[c];
  for (int k = 0; k < 3; ++k) J.col(3 + k) += weight * ws.origin_rpy_axes[c].col(k).cross(arm);
}

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
    T = ws->link_pose[link.parent] * ws->link_origin[i];
    if (const int c = ws->correction_of_link[i]; c >= 0) {
      ws->origin_frame[c] = ws->link_pose[link.parent].linear() * link.origin.linear();
      ws->origin_rpy_axes[c] = ws->origin_frame[c] * ws->origin_rpy_local[c];
      ws->origin_point[c] = T.translation();
    }
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
