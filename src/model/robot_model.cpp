// RobotModel's queries (the URDF loading is io/urdf_loader.cpp).
#include "stac/robot_model.hpp"

namespace stac {

const std::string& RobotModel::qName(int i) const {
  return movable_[q_joints_.at(i)].name;
}

std::optional<int> RobotModel::qIndex(const std::string& joint_name) const {
  auto it = q_by_name_.find(joint_name);
  if (it == q_by_name_.end()) return std::nullopt;
  return it->second;
}

std::optional<int> RobotModel::movableJointIndex(
    const std::string& joint_name) const {
  auto it = movable_by_name_.find(joint_name);
  if (it == movable_by_name_.end()) return std::nullopt;
  return it->second;
}

std::optional<int> RobotModel::linkIndex(const std::string& link_name) const {
  auto it = link_by_name_.find(link_name);
  if (it == link_by_name_.end()) return std::nullopt;
  return it->second;
}

std::optional<int> RobotModel::linkOfJoint(const std::string& joint_name) const {
  for (int l = 0; l < numLinks(); ++l)
    if (links_[l].parent >= 0 && links_[l].joint_name == joint_name) return l;
  return std::nullopt;
}

void RobotModel::expand(const Eigen::VectorXd& q,
                        Eigen::VectorXd* movable_q) const {
  movable_q->resize(static_cast<Eigen::Index>(movable_.size()));
  for (size_t i = 0; i < movable_.size(); ++i) {
    const MovableJoint& mj = movable_[i];
    (*movable_q)[i] = mj.multiplier * q[mj.q_index] + mj.offset;
  }
}

}  // namespace stac
