// The sensor models of SPEC §1, forward maps and inverses, for code that runs
// on the robot (firmware, real-time loops).
//
// Header-only and Eigen-only: no Ceres, no URDF, no YAML, no exceptions, no
// heap allocation. Every function is a template on the scalar type, so a
// microcontroller with a single-precision FPU can use float; C++11 is enough.
// The target is stac::runtime (find_package(stac CONFIG COMPONENTS runtime)).
//
//   joint sensor       p = gain * q + bias            q = (p - bias) / gain
//   tendon (coupling)  L = Σ_j c_j q_j
//   tendon (any)       p = gain * L + bias            L = (p - bias) / gain
//   tendon (path)      L = Σ_k |a_{k+1} - a_k|        (anchors in one frame)
//   marker             x = R (T d) + t                d = T⁻¹ Rᵀ (x - t)
//
// with T the pose of the marker's link in the robot base frame (from the
// robot's own forward kinematics), d the marker in the link frame and (R, t)
// the mocap frame: the pose of the robot base in the mocap frame.
//
// The inverses divide by gain: a calibrated sensor has gain != 0, and that is
// the caller's precondition (nothing here checks or throws).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstddef>

namespace stac {
namespace runtime {

// ---- Linear sensors: joint sensors and tendon sensors ----

// p = gain * value + bias, for a joint sensor (value = joint angle, rad, or
// position, m) or a tendon sensor (value = length L, m).
template <typename T>
struct LinearSensor {
  T gain;
  T bias;

  // The raw reading the sensor gives for `value`.
  T reading(T value) const { return gain * value + bias; }
  // The value a raw reading stands for: (p - bias) / gain.
  T value(T raw) const { return (raw - bias) / gain; }
};

// Joint sensor: p = gain * q + bias.
template <typename T>
inline T jointReading(T q, T gain, T bias) {
  return gain * q + bias;
}
// Its inverse: q = (p - bias) / gain.
template <typename T>
inline T jointAngle(T raw, T gain, T bias) {
  return (raw - bias) / gain;
}

// Tendon sensor: p = gain * L + bias.
template <typename T>
inline T tendonReading(T length, T gain, T bias) {
  return gain * length + bias;
}
// Its inverse: L = (p - bias) / gain.
template <typename T>
inline T tendonLength(T raw, T gain, T bias) {
  return (raw - bias) / gain;
}

// ---- Tendon length models ----

// Coupling: L = Σ_j c_j q_j, with c and q vectors of the same size (the
// angles of the joints the tendon spans, in the order of the coefficients).
template <typename DerivedC, typename DerivedQ>
inline typename DerivedC::Scalar couplingLength(const Eigen::MatrixBase<DerivedC>& c,
                                                const Eigen::MatrixBase<DerivedQ>& q) {
  return c.dot(q);
}
// The same over plain arrays of n entries.
template <typename T>
inline T couplingLength(const T* c, const T* q, std::size_t n) {
  T length = T(0);
  for (std::size_t j = 0; j < n; ++j) length += c[j] * q[j];
  return length;
}

// Path: the length of the polyline through the anchors, all expressed in one
// frame (e.g. the base frame: anchor = T_link * point). Fewer than two points
// give 0.
template <typename T>
inline T pathLength(const Eigen::Matrix<T, 3, 1>* points, std::size_t n) {
  T length = T(0);
  for (std::size_t k = 1; k < n; ++k) length += (points[k] - points[k - 1]).norm();
  return length;
}
// The same for a 3 x N matrix whose columns are the points.
template <typename Derived>
inline typename Derived::Scalar pathLength(const Eigen::MatrixBase<Derived>& points) {
  typedef typename Derived::Scalar T;
  T length = T(0);
  for (Eigen::Index k = 1; k < points.cols(); ++k)
    length += (points.col(k) - points.col(k - 1)).norm();
  return length;
}

// ---- Motion-capture markers ----

// The pose of the robot base in the mocap frame: x_mocap = R x_base + t.
template <typename T>
struct MocapFrame {
  Eigen::Quaternion<T> rotation;
  Eigen::Matrix<T, 3, 1> translation;
};

// x = R (T d) + t: where the mocap system sees marker d (in the frame of a
// link whose pose in the base frame is link_pose).
template <typename T>
inline Eigen::Matrix<T, 3, 1> markerPosition(
    const Eigen::Quaternion<T>& rotation, const Eigen::Matrix<T, 3, 1>& translation,
    const Eigen::Transform<T, 3, Eigen::Isometry>& link_pose,
    const Eigen::Matrix<T, 3, 1>& marker_in_link) {
  return rotation * (link_pose * marker_in_link) + translation;
}
template <typename T>
inline Eigen::Matrix<T, 3, 1> markerPosition(
    const MocapFrame<T>& frame, const Eigen::Transform<T, 3, Eigen::Isometry>& link_pose,
    const Eigen::Matrix<T, 3, 1>& marker_in_link) {
  return markerPosition(frame.rotation, frame.translation, link_pose, marker_in_link);
}

// Its inverse: d = T⁻¹ Rᵀ (x - t), the link-frame position of a marker seen
// at x by the mocap system (R must be a unit quaternion).
template <typename T>
inline Eigen::Matrix<T, 3, 1> markerInLink(
    const Eigen::Quaternion<T>& rotation, const Eigen::Matrix<T, 3, 1>& translation,
    const Eigen::Transform<T, 3, Eigen::Isometry>& link_pose,
    const Eigen::Matrix<T, 3, 1>& marker_in_mocap) {
  return link_pose.inverse(Eigen::Isometry) *
         (rotation.conjugate() * (marker_in_mocap - translation));
}
template <typename T>
inline Eigen::Matrix<T, 3, 1> markerInLink(
    const MocapFrame<T>& frame, const Eigen::Transform<T, 3, Eigen::Isometry>& link_pose,
    const Eigen::Matrix<T, 3, 1>& marker_in_mocap) {
  return markerInLink(frame.rotation, frame.translation, link_pose, marker_in_mocap);
}

}  // namespace runtime
}  // namespace stac
