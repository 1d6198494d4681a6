// Monolithic mode (--method joint): one Ceres problem over every q_t and θ.
//
// Parameter blocks, one per physical quantity: q_t per frame (first
// elimination group, so DENSE_SCHUR reduces the system to θ alone), the
// mocap rotation (unit quaternion on Ceres's QuaternionManifold), the mocap
// translation, each marker position and each sensor's (gain, bias). One
// residual block per reading, so a robust loss applies per reading, exactly
// as in the alternation (measurement.cpp).
//
// Every marker and path-tendon residual needs the frame's forward
// kinematics; an EvaluationCallback computes it once per frame and
// evaluation point, in parallel, before Ceres evaluates the residual blocks,
// which then only read it (no mutable state inside const Evaluate calls).
#include <ceres/ceres.h>
#include <ceres/manifold.h>

#include <array>
#include <cmath>
#include <memory>

#include "methods/monolithic.hpp"
#include "stac/calibrate.hpp"
#include "solve/parallel.hpp"
#include "solve/q_phase.hpp"
#include "stac/sensor_models.hpp"

namespace stac {
namespace {

// Forward kinematics of every frame at the current parameter values.
class KinematicsCache : public ceres::EvaluationCallback {
 public:
  KinematicsCache(const RobotModel& robot, const RowMatrix* q, int threads)
      : robot_(robot), q_(q), threads_(threads),
        frames_(q->rows(), KinematicsWorkspace(robot)) {}

  void PrepareForEvaluation(bool /*evaluate_jacobians*/, bool new_evaluation_point) override {
    if (!new_evaluation_point && valid_) return;
    const int T = static_cast<int>(q_->rows());
    parallelFor(numChunks(T), threads_, [&](int chunk, int) {
      Eigen::VectorXd qt(robot_.dof());
      const int end = std::min(T, (chunk + 1) * kFramesPerChunk);
      for (int t = chunk * kFramesPerChunk; t < end; ++t) {
        qt = q_->row(t).transpose();
        forwardKinematics(robot_, qt, &frames_[t]);
      }
    });
    valid_ = true;
  }

  const KinematicsWorkspace& frame(int t) const { return frames_[t]; }

 private:
  const RobotModel& robot_;
  const RowMatrix* q_;
  int threads_;
  std::vector<KinematicsWorkspace> frames_;
  bool valid_ = false;
};

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

// x = R (h_k(q) d) + t; blocks [q_t, rotation(4), translation(3), d(3)].
class MarkerReadingCost : public ceres::CostFunction {
 public:
  MarkerReadingCost(const RobotModel& robot, const KinematicsCache& cache, int frame, int link,
                    const Eigen::Vector3d& x, double sigma)
      : robot_(robot), cache_(cache), frame_(frame), link_(link), x_(x), inv_(1.0 / sigma) {
    set_num_residuals(3);
    *mutable_parameter_block_sizes() = {robot.dof(), 4, 3, 3};
  }
  bool Evaluate(double const* const* p, double* residuals, double** jac) const override {
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
    return true;
  }

 private:
  const RobotModel& robot_;
  const KinematicsCache& cache_;
  int frame_, link_;
  Eigen::Vector3d x_;
  double inv_;
};

// p = gain * value(q) + bias; blocks [q_t, (gain, bias)]. value is the
// joint angle (joint sensor) or tendon length (tendon sensor).
class ScalarReadingCost : public ceres::CostFunction {
 public:
  ScalarReadingCost(const RobotModel& robot, const KinematicsCache& cache, int frame,
                    const JointSensorConfig* joint, const TendonSensorConfig* tendon, double p,
                    double sigma)
      : robot_(robot), cache_(cache), frame_(frame), joint_(joint), tendon_(tendon), p_(p),
        inv_(1.0 / sigma) {
    set_num_residuals(1);
    *mutable_parameter_block_sizes() = {robot.dof(), 2};
  }
  bool Evaluate(double const* const* p, double* residuals, double** jac) const override {
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
    return true;
  }

 private:
  const RobotModel& robot_;
  const KinematicsCache& cache_;
  int frame_;
  const JointSensorConfig* joint_;
  const TendonSensorConfig* tendon_;
  double p_, inv_;
};

}  // namespace

void solveJointProblem(const MeasurementModel& model, const NoiseModel& noise,
                       const RobustLoss& loss, const Observations& obs,
                       const CalibrationOptions& options, SensorParameters* theta,
                       QState* state, int* iterations, bool* converged) {
  const RobotModel& robot = model.robot();
  const SensorSet& sensors = model.sensors();
  const int T = obs.num_frames;
  const int threads = resolveThreads(options.threads);
  auto cache = std::make_unique<KinematicsCache>(robot, &state->q, threads);

  // Parameter storage at stable addresses (Ceres keeps raw pointers).
  double rotation[4] = {theta->mocap.rotation.w(), theta->mocap.rotation.x(),
                        theta->mocap.rotation.y(), theta->mocap.rotation.z()};
  double translation[3] = {theta->mocap.translation.x(), theta->mocap.translation.y(),
                           theta->mocap.translation.z()};
  std::vector<std::array<double, 3>> markers(sensors.markers.size());
  for (size_t m = 0; m < markers.size(); ++m)
    for (int i = 0; i < 3; ++i) markers[m][i] = theta->marker_position[m][i];
  std::vector<std::array<double, 2>> joints(sensors.joint_sensors.size()),
      tendons(sensors.tendon_sensors.size());
  for (size_t s = 0; s < joints.size(); ++s)
    joints[s] = {theta->joint_sensor[s].gain, theta->joint_sensor[s].bias};
  for (size_t s = 0; s < tendons.size(); ++s)
    tendons[s] = {theta->tendon_sensor[s].gain, theta->tendon_sensor[s].bias};

  ceres::Problem::Options po;
  po.evaluation_callback = cache.get();
  po.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(po);
  std::unique_ptr<ceres::LossFunction> loss_fn(loss.makeCeresLoss());
  auto ordering = std::make_shared<ceres::ParameterBlockOrdering>();

  for (int t = 0; t < T; ++t) {
    double* qt = state->q.row(t).data();
    const double* xm = obs.marker.cols() ? obs.marker.row(t).data() : nullptr;
    for (size_t m = 0; m < sensors.markers.size(); ++m) {
      const double* x = xm + 3 * m;
      if (std::isnan(x[0])) continue;
      problem.AddResidualBlock(
          new MarkerReadingCost(robot, *cache, t, sensors.markers[m].link,
                                Eigen::Vector3d(x[0], x[1], x[2]), noise.marker[m]),
          loss_fn.get(), qt, rotation, translation, markers[m].data());
    }
    for (size_t s = 0; s < sensors.joint_sensors.size(); ++s) {
      const double p = obs.joint(t, s);
      if (std::isnan(p)) continue;
      problem.AddResidualBlock(new ScalarReadingCost(robot, *cache, t, &sensors.joint_sensors[s],
                                                     nullptr, p, noise.joint[s]),
                               loss_fn.get(), qt, joints[s].data());
    }
    for (size_t s = 0; s < sensors.tendon_sensors.size(); ++s) {
      const double p = obs.tendon(t, s);
      if (std::isnan(p)) continue;
      problem.AddResidualBlock(new ScalarReadingCost(robot, *cache, t, nullptr,
                                                     &sensors.tendon_sensors[s], p,
                                                     noise.tendon[s]),
                               loss_fn.get(), qt, tendons[s].data());
    }
    if (problem.HasParameterBlock(qt)) ordering->AddElementToGroup(qt, 0);
  }
  auto theta_block = [&](double* block, bool fixed) {
    if (!problem.HasParameterBlock(block)) return;
    ordering->AddElementToGroup(block, 1);
    if (fixed) problem.SetParameterBlockConstant(block);
  };
  if (problem.HasParameterBlock(rotation)) {
    problem.SetManifold(rotation, new ceres::QuaternionManifold);
    theta_block(rotation, sensors.mocap_frame_fixed);
    theta_block(translation, sensors.mocap_frame_fixed);
  }
  for (size_t m = 0; m < markers.size(); ++m) theta_block(markers[m].data(), sensors.markers[m].fixed);
  for (size_t s = 0; s < joints.size(); ++s) theta_block(joints[s].data(), sensors.joint_sensors[s].fixed);
  for (size_t s = 0; s < tendons.size(); ++s) theta_block(tendons[s].data(), sensors.tendon_sensors[s].fixed);

  ceres::Solver::Options so;
  so.minimizer_type = ceres::TRUST_REGION;
  so.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  so.linear_solver_type = ceres::DENSE_SCHUR;
  so.linear_solver_ordering = ordering;
  so.num_threads = threads;
  so.max_num_iterations = options.max_iterations;
  so.function_tolerance = std::max(options.tolerance, 1e-16);
  so.gradient_tolerance = 1e-14;
  so.parameter_tolerance = 1e-12;
  so.logging_type = ceres::SILENT;
  so.minimizer_progress_to_stdout = false;
  ceres::Solver::Summary summary;
  ceres::Solve(so, &problem, &summary);

  *iterations = static_cast<int>(summary.iterations.size()) - 1;
  *converged = summary.termination_type == ceres::CONVERGENCE;
  theta->mocap.rotation =
      Eigen::Quaterniond(rotation[0], rotation[1], rotation[2], rotation[3]).normalized();
  theta->mocap.translation = Eigen::Vector3d(translation[0], translation[1], translation[2]);
  for (size_t m = 0; m < markers.size(); ++m)
    theta->marker_position[m] = Eigen::Vector3d(markers[m][0], markers[m][1], markers[m][2]);
  for (size_t s = 0; s < joints.size(); ++s) theta->joint_sensor[s] = {joints[s][0], joints[s][1]};
  for (size_t s = 0; s < tendons.size(); ++s)
    theta->tendon_sensor[s] = {tendons[s][0], tendons[s][1]};
}

}  // namespace stac
