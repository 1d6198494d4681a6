// Kinematic calibration (SPEC §3 "Kinematic calibration: joint origins"):
// corrections to the <origin> of chosen URDF joints, estimated with the
// sensors. The corrected transform from the parent link to the joint frame
// is T(urdf origin) · T(xyz, rpy): the correction acts after the URDF's own
// origin, in the frame that origin places.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>

namespace stac {

// One joint's correction: a translation (metres) and a roll-pitch-yaw
// rotation (radians, URDF convention R = Rz(yaw) Ry(pitch) Rx(roll)).
struct OriginCorrection {
  Eigen::Vector3d xyz = Eigen::Vector3d::Zero();
  Eigen::Vector3d rpy = Eigen::Vector3d::Zero();

  Eigen::Isometry3d transform() const;
  // The rotation's partial derivatives as angular velocities: dR/d rpy_k =
  // [ω_k]× R, columns ω_roll, ω_pitch, ω_yaw, in the frame the URDF origin
  // places (so d(T p)/d rpy_k = ω_k × (R p)).
  Eigen::Matrix3d rpyAxes() const;
};

// Which parts of a correction are held (`fixed: true`, `[xyz]`, `[rpy]`).
struct FixedOrigin {
  bool xyz = false;
  bool rpy = false;
  static FixedOrigin both(bool held) { return {held, held}; }
  bool all() const { return xyz && rpy; }
  bool any() const { return xyz || rpy; }
};

struct JointOriginConfig {
  std::string joint_name;
  int link = -1;  // RobotModel link index of the link the joint attaches
  FixedOrigin fixed;
};

// Gaussian prior (MAP) on every free component: one std for the
// translations, one for the rotations; 0 = no prior on that part.
struct OriginPrior {
  double xyz = 0.0;  // metres
  double rpy = 0.0;  // radians
  bool any() const { return xyz > 0 || rpy > 0; }
};

// `--origin-prior`'s default (SPEC §4).
constexpr double kDefaultOriginPriorXyz = 0.005;
constexpr double kDefaultOriginPriorRpy = 0.01;

}  // namespace stac
