// The mocap frame's rotation as the sensors file spells it (SPEC §3):
// roll-pitch-yaw in the URDF convention and [w, x, y, z] unit quaternions.
// Shared by the reader and the writer so that both read the same convention.
#pragma once

#include <Eigen/Geometry>
#include <cmath>

namespace stac {

// URDF convention: R = Rz(yaw) Ry(pitch) Rx(roll).
inline Eigen::Quaterniond fromRpy(const Eigen::Vector3d& rpy) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(rpy[2], Eigen::Vector3d::UnitZ()) *
                            Eigen::AngleAxisd(rpy[1], Eigen::Vector3d::UnitY()) *
                            Eigen::AngleAxisd(rpy[0], Eigen::Vector3d::UnitX()));
}

// The roll-pitch-yaw of a rotation, accurate to ~1e-8 rad everywhere. Away
// from gimbal lock the usual atan2 formulas; as |cos(pitch)| -> 0 roll and
// yaw lose their meaning (only yaw ∓ roll is defined) and their atan2
// arguments shrink to rounding noise, so near the lock the decomposition
// with roll = 0 is also tried and the better of the two kept.
inline Eigen::Vector3d toRpy(const Eigen::Quaterniond& q) {
  const Eigen::Matrix3d R = q.toRotationMatrix();
  const double c = std::hypot(R(0, 0), R(1, 0));  // cos(pitch) >= 0
  const double pitch = std::atan2(-R(2, 0), c);
  const Eigen::Vector3d regular(std::atan2(R(2, 1), R(2, 2)), pitch, std::atan2(R(1, 0), R(0, 0)));
  if (c > 1e-4) return regular;
  // R01 = -sin(yaw ∓ roll), R11 = cos(yaw ∓ roll) when cos(pitch) = 0.
  const Eigen::Vector3d locked(0.0, pitch, std::atan2(-R(0, 1), R(1, 1)));
  return fromRpy(regular).angularDistance(q) <= fromRpy(locked).angularDistance(q) ? regular
                                                                                   : locked;
}

// A unit quaternion: unchanged if it already is one to rounding (so that
// writing and reading it back is exact), else normalized.
inline Eigen::Quaterniond unitQuaternion(const Eigen::Quaterniond& q) {
  if (std::abs(q.squaredNorm() - 1.0) <= 1e-14) return q;
  return q.normalized();
}

}  // namespace stac
