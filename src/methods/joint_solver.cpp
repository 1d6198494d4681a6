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
#include "methods/monolithic_costs.hpp"
#include "stac/calibrate.hpp"
#include "solve/parallel.hpp"
#include "solve/q_phase.hpp"
#include "stac/sensor_models.hpp"

namespace stac {
using monolithic::KinematicsCache;
using monolithic::MarkerReadingCost;
using monolithic::ScalarReadingCost;

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
