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
#include <functional>
#include <memory>

#include "methods/monolithic.hpp"
#include "methods/monolithic_costs.hpp"
#include "stac/calibrate.hpp"
#include "stac/error.hpp"
#include "solve/parallel.hpp"
#include "solve/q_phase.hpp"
#include "stac/sensor_models.hpp"

namespace stac {
using monolithic::KinematicsCache;
using monolithic::MarkerReadingCost;
using monolithic::ScalarReadingCost;

namespace {

// θ's parameter blocks in one buffer, in θ's order: rotation (w, x, y, z) |
// translation | marker positions | joint (gain, bias) | tendon (gain, bias) |
// joint-origin corrections (x, y, z, roll, pitch, yaw).
// Ceres orders a group's blocks by address, so keeping them in one buffer
// makes that order (and the rounding of the reduced system) the same
// wherever the heap puts them. Stable addresses: Ceres keeps raw pointers.
class ThetaBlocks {
 public:
  explicit ThetaBlocks(const SensorParameters& theta)
      : markers_(theta.marker_position.size()), joints_(theta.joint_sensor.size()),
        tendons_(theta.tendon_sensor.size()),
        values_(7 + 3 * markers_ + 2 * joints_ + 2 * tendons_ + 6 * theta.joint_origin.size()) {
    const Eigen::Quaterniond& r = theta.mocap.rotation;
    values_[0] = r.w(), values_[1] = r.x(), values_[2] = r.y(), values_[3] = r.z();
    for (int i = 0; i < 3; ++i) translation()[i] = theta.mocap.translation[i];
    for (size_t m = 0; m < markers_; ++m)
      for (int i = 0; i < 3; ++i) marker(m)[i] = theta.marker_position[m][i];
    for (size_t s = 0; s < joints_; ++s)
      joint(s)[0] = theta.joint_sensor[s].gain, joint(s)[1] = theta.joint_sensor[s].bias;
    for (size_t s = 0; s < theta.tendon_sensor.size(); ++s)
      tendon(s)[0] = theta.tendon_sensor[s].gain, tendon(s)[1] = theta.tendon_sensor[s].bias;
    for (size_t c = 0; c < theta.joint_origin.size(); ++c)
      for (int i = 0; i < 3; ++i)
        origin(c)[i] = theta.joint_origin[c].xyz[i], origin(c)[3 + i] = theta.joint_origin[c].rpy[i];
  }
  double* rotation() { return values_.data(); }
  double* translation() { return values_.data() + 4; }
  double* marker(size_t m) { return values_.data() + 7 + 3 * m; }
  double* joint(size_t s) { return values_.data() + 7 + 3 * markers_ + 2 * s; }
  double* tendon(size_t s) { return values_.data() + 7 + 3 * markers_ + 2 * joints_ + 2 * s; }
  double* origin(size_t c) {
    return values_.data() + 7 + 3 * markers_ + 2 * joints_ + 2 * tendons_ + 6 * c;
  }

  void copyTo(SensorParameters* theta) {
    const double* q = rotation();
    theta->mocap.rotation = Eigen::Quaterniond(q[0], q[1], q[2], q[3]).normalized();
    theta->mocap.translation = Eigen::Map<const Eigen::Vector3d>(translation());
    for (size_t m = 0; m < markers_; ++m)
      theta->marker_position[m] = Eigen::Map<const Eigen::Vector3d>(marker(m));
    for (size_t s = 0; s < joints_; ++s) theta->joint_sensor[s] = {joint(s)[0], joint(s)[1]};
    for (size_t s = 0; s < theta->tendon_sensor.size(); ++s)
      theta->tendon_sensor[s] = {tendon(s)[0], tendon(s)[1]};
    for (size_t c = 0; c < theta->joint_origin.size(); ++c) {
      theta->joint_origin[c].xyz = Eigen::Map<const Eigen::Vector3d>(origin(c));
      theta->joint_origin[c].rpy = Eigen::Map<const Eigen::Vector3d>(origin(c) + 3);
    }
  }

 private:
  size_t markers_, joints_, tendons_;
  std::vector<double> values_;
};

// One residual block per available reading of frame t; q_t joins the first
// elimination group.
void addFrame(const MeasurementModel& model, const NoiseModel& noise, const Observations& obs,
              int t, const KinematicsCache& cache, ceres::LossFunction* loss, double* qt,
              ThetaBlocks* theta, ceres::Problem* problem, ceres::ParameterBlockOrdering* order) {
  const RobotModel& robot = model.robot();
  const SensorSet& sensors = model.sensors();
  const double* xm = obs.marker.cols() ? obs.marker.row(t).data() : nullptr;
  for (size_t m = 0; m < sensors.markers.size(); ++m) {
    const double* x = xm + 3 * m;
    if (std::isnan(x[0])) continue;
    const std::vector<int>& origins = model.markerOrigins(static_cast<int>(m));
    std::vector<double*> blocks = {qt, theta->rotation(), theta->translation(), theta->marker(m)};
    for (int c : origins) blocks.push_back(theta->origin(c));
    problem->AddResidualBlock(
        new MarkerReadingCost(robot, cache, t, sensors.markers[m].link,
                              Eigen::Vector3d(x[0], x[1], x[2]), noise.marker[m], origins),
        loss, blocks);
  }
  for (size_t s = 0; s < sensors.joint_sensors.size(); ++s) {
    const double p = obs.joint(t, s);
    if (std::isnan(p)) continue;
    problem->AddResidualBlock(new ScalarReadingCost(robot, cache, t, &sensors.joint_sensors[s],
                                                    nullptr, p, noise.joint[s]),
                              loss, qt, theta->joint(s));
  }
  for (size_t s = 0; s < sensors.tendon_sensors.size(); ++s) {
    const double p = obs.tendon(t, s);
    if (std::isnan(p)) continue;
    const int si = static_cast<int>(s);
    std::vector<double*> blocks = {qt, theta->tendon(s)};
    for (int c : model.tendonOrigins(si)) blocks.push_back(theta->origin(c));
    problem->AddResidualBlock(new ScalarReadingCost(robot, cache, t, nullptr,
                                                    &sensors.tendon_sensors[s], p, noise.tendon[s],
                                                    model.tendonOrigins(si),
                                                    model.anchorOriginSlots(si)),
                              loss, blocks);
  }
  if (problem->HasParameterBlock(qt)) order->AddElementToGroup(qt, 0);
}

// θ's blocks in the second elimination group, held ones constant; a (gain,
// bias) block with one entry held keeps it by a SubsetManifold.
void addThetaBlocks(const SensorSet& sensors, ThetaBlocks* theta, ceres::Problem* problem,
                    ceres::ParameterBlockOrdering* order) {
  auto block = [&](double* b, bool fixed) {
    if (!problem->HasParameterBlock(b)) return;
    order->AddElementToGroup(b, 1);
    if (fixed) problem->SetParameterBlockConstant(b);
  };
  auto gainBias = [&](double* b, const FixedGainBias& fixed) {
    block(b, fixed.all());
    if (problem->HasParameterBlock(b) && fixed.any() && !fixed.all())
      problem->SetManifold(b, new ceres::SubsetManifold(2, {fixed.gain ? 0 : 1}));
  };
  if (problem->HasParameterBlock(theta->rotation())) {
    problem->SetManifold(theta->rotation(), new ceres::QuaternionManifold);
    block(theta->rotation(), sensors.mocap_frame_fixed.rotation);
    block(theta->translation(), sensors.mocap_frame_fixed.translation);
  }
  for (size_t m = 0; m < sensors.markers.size(); ++m)
    block(theta->marker(m), sensors.markers[m].fixed);
  for (size_t s = 0; s < sensors.joint_sensors.size(); ++s)
    gainBias(theta->joint(s), sensors.joint_sensors[s].fixed);
  for (size_t s = 0; s < sensors.tendon_sensors.size(); ++s)
    gainBias(theta->tendon(s), sensors.tendon_sensors[s].fixed);
  // Joint-origin corrections: a part held by a SubsetManifold, the prior a
  // residual block of its own.
  const OriginPrior& prior = sensors.origin_prior;
  for (size_t c = 0; c < sensors.joint_origins.size(); ++c) {
    double* b = theta->origin(c);
    const FixedOrigin& fixed = sensors.joint_origins[c].fixed;
    if (!problem->HasParameterBlock(b)) continue;
    if (prior.any() && !fixed.all())
      problem->AddResidualBlock(new monolithic::OriginPriorCost(prior.xyz, prior.rpy, fixed), nullptr,
                                b);
    block(b, fixed.all());
    if (fixed.any() && !fixed.all())
      problem->SetManifold(b, new ceres::SubsetManifold(6, fixed.xyz ? std::vector<int>{0, 1, 2}
                                                                     : std::vector<int>{3, 4, 5}));
  }
}

// CalibrationOptions::should_stop polled after every Ceres iteration: a
// long joint solve stops within one iteration, not at its end.
class StopCallback : public ceres::IterationCallback {
 public:
  explicit StopCallback(const std::function<bool()>& should_stop) : should_stop_(should_stop) {}
  ceres::CallbackReturnType operator()(const ceres::IterationSummary&) override {
    return should_stop_() ? ceres::SOLVER_ABORT : ceres::SOLVER_CONTINUE;
  }

 private:
  const std::function<bool()>& should_stop_;
};

ceres::Solver::Options solverOptions(const CalibrationOptions& options, int threads,
                                     std::shared_ptr<ceres::ParameterBlockOrdering> order) {
  ceres::Solver::Options so;
  so.minimizer_type = ceres::TRUST_REGION;
  so.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  so.linear_solver_type = ceres::DENSE_SCHUR;
  so.linear_solver_ordering = std::move(order);
  so.num_threads = threads;
  so.max_num_iterations = options.max_iterations;
  so.function_tolerance = std::max(options.tolerance, 1e-16);
  so.gradient_tolerance = 1e-14;
  so.parameter_tolerance = 1e-12;
  so.logging_type = ceres::SILENT;
  so.minimizer_progress_to_stdout = false;
  return so;
}

}  // namespace

void solveMonolithic(const MeasurementModel& model, const NoiseModel& noise,
                       const RobustLoss& loss, const Observations& obs,
                       const CalibrationOptions& options, SensorParameters* theta,
                       QState* state, int* iterations, bool* converged) {
  const int threads = resolveThreads(options.threads);
  ThetaBlocks blocks(*theta);
  auto cache = std::make_unique<KinematicsCache>(
      model.robot(), &state->q, threads, model.thetaSpace().originLinks(),
      model.sensors().joint_origins.empty() ? nullptr : blocks.origin(0));
  ceres::Problem::Options po;
  po.evaluation_callback = cache.get();
  po.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(po);
  std::unique_ptr<ceres::LossFunction> loss_fn(loss.makeCeresLoss());
  auto order = std::make_shared<ceres::ParameterBlockOrdering>();
  for (int t = 0; t < obs.num_frames; ++t)
    addFrame(model, noise, obs, t, *cache, loss_fn.get(), state->q.row(t).data(), &blocks,
             &problem, order.get());
  addThetaBlocks(model.sensors(), &blocks, &problem, order.get());
  ceres::Solver::Options so = solverOptions(options, threads, order);
  StopCallback stop(options.should_stop);
  if (options.should_stop) so.callbacks.push_back(&stop);
  ceres::Solver::Summary summary;
  ceres::Solve(so, &problem, &summary);
  if (options.should_stop && summary.termination_type == ceres::USER_FAILURE) throw Cancelled();
  *iterations = static_cast<int>(summary.iterations.size()) - 1;
  *converged = summary.termination_type == ceres::CONVERGENCE;
  blocks.copyTo(theta);
}

}  // namespace stac
