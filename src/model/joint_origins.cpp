#include "stac/joint_origins.hpp"

namespace stac {

Eigen::Isometry3d OriginCorrection::transform() const {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = (Eigen::AngleAxisd(rpy[2], Eigen::Vector3d::UnitZ()) *
                Eigen::AngleAxisd(rpy[1], Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(rpy[0], Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  T.translation() = xyz;
  return T;
}

Eigen::Matrix3d OriginCorrection::rpyAxes() const {
  // R = Rz(y) Ry(p) Rx(r): dR/dr = [Rz Ry e_x]× R, dR/dp = [Rz e_y]× R,
  // dR/dy = [e_z]× R.
  const Eigen::Matrix3d Rz = Eigen::AngleAxisd(rpy[2], Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Matrix3d Ry = Eigen::AngleAxisd(rpy[1], Eigen::Vector3d::UnitY()).toRotationMatrix();
  Eigen::Matrix3d W;
  W.col(0) = Rz * Ry * Eigen::Vector3d::UnitX();
  W.col(1) = Rz * Eigen::Vector3d::UnitY();
  W.col(2) = Eigen::Vector3d::UnitZ();
  return W;
}

}  // namespace stac
