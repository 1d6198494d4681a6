#include "methods/monolithic_costs.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cassert>

#include "solve/parallel.hpp"
#include "stac/sensor_models.hpp"

namespace stac::monolithic {
namespace {

// d(R(q) y)/d(w, x, y, z) for a unit quaternion (Ceres's [w, x, y, z]).
Eigen::Matrix<double, 3, 4> rotatePointJacobian(const double* quat, const Eigen::Vector3d& y) {
  const double w = quat[0];
  const Eigen::Vector3d v(quat[1], quat[2], quat[3]);
  Eigen::Matrix<double, 3, 4> J;
  J.col(0) = 2 * w * y + 2 * v.cross(y);
  for (int i = 0; i < 3; ++i) {
    const Eigen::Vector3d e = Eigen::Vector3d::Unit(i);
    J.col(1 + i) = -2 * v[i] * y + 2 * y[i] * v + 2 * v.dot(y) * e + 2 * w * e.cross(y);
  }
  return J;
}

Eigen::Matrix3d quaternionMatrix(const double* quat) {
  return Eigen::Quaterniond(quat[0], quat[1], quat[2], quat[3]).normalized().toRotationMatrix();
}

}  // namespace

KinematicsCache::KinematicsCache(const RobotModel& robot, const RowMatrix* q, int threads,
                                 std::vector<int> origin_links, const double* origins)
    : robot_(robot), q_(q), threads_(threads), origin_links_(std::move(origin_links)),
      origins_(origins), frames_(q->rows(), KinematicsWorkspace(robot)) {}

void KinematicsCache::PrepareForEvaluation(bool /*evaluate_jacobians*/,
                                           bool new_evaluation_point) {
  if (!new_evaluation_point && valid_) return;
  const int T = static_cast<int>(q_->rows());
  std::vector<OriginCorrection> corrections(origin_links_.size());
  for (size_t c = 0; c < corrections.size(); ++c) {
    corrections[c].xyz = Eigen::Map<const Eigen::Vector3d>(origins_ + 6 * c);
    corrections[c].rpy = Eigen::Map<const Eigen::Vector3d>(origins_ + 6 * c + 3);
  }
  parallelFor(numChunks(T), threads_, [&](int chunk, int) {
    Eigen::VectorXd qt(robot_.dof());
    const int end = std::min(T, (chunk + 1) * kFramesPerChunk);
    for (int t = chunk * kFramesPerChunk; t < end; ++t) {
      qt = q_->row(t).transpose();
      setOriginCorrections(robot_, origin_links_, corrections, &frames_[t]);
      forwardKinematics(robot_, qt, &frames_[t]);
    }
  });
  valid_ = true;
}

MarkerReadingCost::MarkerReadingCost(const RobotModel& robot, const KinematicsCache& cache,
                                     int frame, int link, const Eigen::Vector3d& x,
                                     double sigma, std::vector<int> origins)
    : robot_(robot), cache_(cache), frame_(frame), link_(link), x_(x), inv_(1.0 / sigma),
      origins_(std::move(origins)) {
  set_num_residuals(3);
  *mutable_parameter_block_sizes() = {robot.dof(), 4, 3, 3};
  for (size_t i = 0; i < origins_.size(); ++i) mutable_parameter_block_sizes()->push_back(6);
}

ceres::CostFunction* MarkerReadingCost::Create(const RobotModel& robot,
                                               const KinematicsCache& cache, int frame,
                                               int link, const Eigen::Vector3d& x,
                                               double sigma) {
  return new MarkerReadingCost(robot, cache, frame, link, x, sigma);
}

bool MarkerReadingCost::Evaluate(double const* const* p, double* residuals,
                                 double** jac) const {
  const KinematicsWorkspace& ws = cache_.frame(frame_);
  const Eigen::Vector3d d(p[3][0], p[3][1], p[3][2]);
  const Eigen::Vector3d t(p[2][0], p[2][1], p[2][2]);
  const Eigen::Matrix3d R = quaternionMatrix(p[1]);
  const Eigen::Vector3d xb = marker_sensor::positionInBase(ws, link_, d);
  Eigen::Map<Eigen::Vector3d> r(residuals);
  r = (R * xb + t - x_) * inv_;
  if (!jac) return true;
  const int dof = robot_.dof();
  if (jac[0]) {
    Eigen::MatrixXd J(3, dof);
    pointJacobian(robot_, ws, link_, xb, J);
    Eigen::Map<Eigen::Matrix<double, 3, Eigen::Dynamic, Eigen::RowMajor>> Jq(jac[0], 3, dof);
    Jq = inv_ * R * J;
  }
  using Rows34 = Eigen::Matrix<double, 3, 4, Eigen::RowMajor>;
  using Rows33 = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>;
  if (jac[1]) {
    Eigen::Map<Rows34> J(jac[1]);
    J = inv_ * rotatePointJacobian(p[1], xb);
  }
  if (jac[2]) {
    Eigen::Map<Rows33> J(jac[2]);
    J = inv_ * Eigen::Matrix3d::Identity();
  }
  if (jac[3]) {
    Eigen::Map<Rows33> J(jac[3]);
    J = inv_ * R * ws.link_pose[link_].linear();
  }
  for (size_t i = 0; i < origins_.size(); ++i) {
    if (!jac[4 + i]) continue;
    Eigen::Matrix<double, 3, 6> Jo = Eigen::Matrix<double, 3, 6>::Zero();
    addOriginJacobian(ws, origins_[i], xb, 1.0, Jo);
    Eigen::Map<Eigen::Matrix<double, 3, 6, Eigen::RowMajor>> J(jac[4 + i]);
    J = inv_ * R * Jo;
  }
  return true;
}

OriginPriorCost::OriginPriorCost(double xyz_std, double rpy_std, const FixedOrigin& held) {
  for (int k = 0; k < 6; ++k) {
    const double s = k < 3 ? xyz_std : rpy_std;
    const bool part_held = k < 3 ? held.xyz : held.rpy;
    inv_[k] = s > 0 && !part_held ? 1.0 / s : 0.0;
  }
}

bool OriginPriorCost::Evaluate(double const* const* p, double* residuals, double** jac) const {
  for (int k = 0; k < 6; ++k) residuals[k] = inv_[k] * p[0][k];
  if (jac && jac[0]) {
    Eigen::Map<Eigen::Matrix<double, 6, 6, Eigen::RowMajor>> J(jac[0]);
    J.setZero();
    for (int k = 0; k < 6; ++k) J(k, k) = inv_[k];
  }
  return true;
}

ScalarReadingCost::ScalarReadingCost(const RobotModel& robot, const KinematicsCache& cache,
                                     int frame, const JointSensorConfig* joint,
                                     const TendonSensorConfig* tendon, double p, double sigma,
                                     std::vector<int> origins,
                                     std::vector<std::vector<int>> anchor_slots)
    : robot_(robot), cache_(cache), frame_(frame), joint_(joint), tendon_(tendon), p_(p),
      inv_(1.0 / sigma), origins_(std::move(origins)), anchor_slots_(std::move(anchor_slots)) {
  assert((joint == nullptr) != (tendon == nullptr));
  set_num_residuals(1);
  *mutable_parameter_block_sizes() = {robot.dof(), 2};
  for (size_t i = 0; i < origins_.size(); ++i) mutable_parameter_block_sizes()->push_back(6);
}

ceres::CostFunction* ScalarReadingCost::Create(const RobotModel& robot,
                                               const KinematicsCache& cache, int frame,
                                               const JointSensorConfig* joint,
                                               const TendonSensorConfig* tendon, double p,
                                               double sigma) {
  return new ScalarReadingCost(robot, cache, frame, joint, tendon, p, sigma);
}

bool ScalarReadingCost::Evaluate(double const* const* p, double* residuals,
                                 double** jac) const {
  const int dof = robot_.dof();
  const double gain = p[1][0], bias = p[1][1];
  double value;
  const KinematicsWorkspace& ws = cache_.frame(frame_);
  if (joint_) {
    const MovableJoint& mj = robot_.movableJoints()[joint_->joint];
    value = mj.multiplier * p[0][mj.q_index] + mj.offset;
  } else {
    value = tendon_sensor::length(robot_, *tendon_, ws);
  }
  residuals[0] = (gain * value + bias - p_) * inv_;
  if (!jac) return true;
  if (jac[0]) {
    Eigen::Map<Eigen::RowVectorXd> row(jac[0], dof);
    row.setZero();
    if (joint_) {
      const MovableJoint& mj = robot_.movableJoints()[joint_->joint];
      row[mj.q_index] = inv_ * gain * mj.multiplier;
    } else {
      tendon_sensor::addLengthJacobian(robot_, *tendon_, ws, inv_ * gain, row);
    }
  }
  if (jac[1]) {
    jac[1][0] = inv_ * value;
    jac[1][1] = inv_;
  }
  if (origins_.empty()) return true;
  Eigen::RowVectorXd row = Eigen::RowVectorXd::Zero(6 * origins_.size());
  tendon_sensor::addOriginLengthJacobian(*tendon_, ws, origins_, anchor_slots_, inv_ * gain, row);
  for (size_t i = 0; i < origins_.size(); ++i)
    if (jac[2 + i]) std::copy(row.data() + 6 * i, row.data() + 6 * i + 6, jac[2 + i]);
  return true;
}

}  // namespace stac::monolithic
