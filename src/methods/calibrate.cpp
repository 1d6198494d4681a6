// calibrate(): validates, builds the problem once, runs the chosen method
// (method.hpp) and builds its result.
#include "stac/calibrate.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "methods/method.hpp"
#include "stac/error.hpp"
#include "solve/parallel.hpp"
#include "solve/spike_screen.hpp"

namespace stac {

bool CalibrationOptions::isValid(std::string* error) const {
  auto fail = [&](const std::string& e) {
    if (error) *error = e;
    return false;
  };
  if (max_iterations < 1) return fail("max_iterations must be at least 1");
  if (!(tolerance >= 0) || !std::isfinite(tolerance))
    return fail("tolerance must be a finite number >= 0");
  if (threads < 0) return fail("threads must be >= 0 (0 = all cores)");
  if (!(loss_scale > 0) || !std::isfinite(loss_scale))
    return fail("loss scale must be positive and finite");
  if (method == Method::kEkf && !ekf.isValid(error)) return false;
  return true;
}

const char* qPhaseName(QPhaseMethod m) {
  switch (m) {
    case QPhaseMethod::kLmIter: return "lm-iter";
    case QPhaseMethod::kLmBatch: return "lm-batch";
    case QPhaseMethod::kBfgs: return "bfgs";
  }
  return "";
}

Eigen::VectorXd neutralPose(const RobotModel& robot) {
  Eigen::VectorXd q = Eigen::VectorXd::Zero(robot.dof());
  for (int i = 0; i < robot.dof(); ++i)
    q[i] = std::clamp(0.0, robot.lowerLimits()[i], robot.upperLimits()[i]);
  return q;
}

namespace {
// Every method reports progress at its natural steps (STAC iterations, EKF
// stretches, classical and joint solves): there the cancellation is polled,
// whether or not the caller wants the reports.
std::function<void(const IterationReport&)> stoppableProgress(const CalibrationOptions& o) {
  return [progress = o.progress, should_stop = o.should_stop](const IterationReport& r) {
    if (should_stop()) throw Cancelled();
    if (progress) progress(r);
  };
}
}  // namespace

CalibrationResult calibrate(const RobotModel& robot, const SensorSet& sensors,
                            const SensorParameters& seed, const Observations& obs,
                            const CalibrationOptions& given, RowMatrix* joint_angles,
                            const RowMatrix* q0) {
  std::string error;
  if (!given.isValid(&error)) throw std::invalid_argument(error);
  if (obs.num_frames < 1) throw std::invalid_argument("the log has no frames");
  if (seed.joint_origin.size() != sensors.joint_origins.size())
    throw std::invalid_argument("the seed has no value for every joint-origin correction");
  if (!sensors.joint_origins.empty() && given.method == Method::kEkf)
    throw std::invalid_argument(
        "--method ekf does not estimate joint-origin corrections (joint_origins, "
        "--joint-origins): use --method stac, joint or classical");
  CalibrationOptions options = given;
  // The EKF starts from one q: q0's first row unless its own is given.
  if (options.method == Method::kEkf && q0 && options.ekf.initial_q.size() == 0)
    options.ekf.initial_q = q0->row(0).transpose();
  if (options.should_stop) options.progress = stoppableProgress(options);
  const Clock::time_point start = Clock::now();
  const MeasurementModel model(robot, sensors);
  const NoiseModel seed_noise = NoiseModel::fromSeeds(sensors);
  const RobustLoss loss(options.loss, options.loss_scale);
  // A robust loss asks for gross readings to be expected: those that stand
  // out in time are set aside before anything is fitted (spike_screen.hpp).
  const bool screened = loss.enabled() && options.screen_spikes;
  SpikeScreen screen;
  if (screened) screen = screenSpikes(obs, seed_noise);
  const Observations& used = screened ? screen.kept : obs;
  const Problem problem{model, used, seed_noise, loss, resolveThreads(options.threads),
                        findMarkerBodies(sensors, used)};
  const MethodInput in{problem, seed, options, start, q0};
  CalibrationResult r = [&] {
    switch (options.method) {
      case Method::kStac: return makeResult(in, runStac(in), joint_angles);
      case Method::kMonolithic: return makeResult(in, runMonolithic(in), joint_angles);
      case Method::kEkf: return makeResult(in, runEkf(in), joint_angles);
      case Method::kClassical: return makeResult(in, runClassical(in), joint_angles);
    }
    throw std::invalid_argument("unknown method");
  }();
  std::copy(screen.set_aside, screen.set_aside + kNumSensorGroups, r.summary.spikes_set_aside);
  return r;
}

CalibrationResult calibrateFromSource(const std::string& sensors_source, const RobotModel& robot,
                                      const SensorSet& sensors, const SensorParameters& seed,
                                      const Observations& obs, const CalibrationOptions& options,
                                      RowMatrix* joint_angles) {
  try {
    return calibrate(robot, sensors, seed, obs, options, joint_angles);
  } catch (const std::invalid_argument& e) {
    throw InputError(sensors_source, e.what());
  }
}

}  // namespace stac
