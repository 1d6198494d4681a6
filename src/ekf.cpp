// The EKF baseline (see ekf.hpp). Frame by frame:
//   predict:  P_qq += Σ_q                                  (eq. 24)
//   linearise every reading at (θ, q):  r (whitened), H = [dr/dθ_free, dr/dq]
//                                                          (eq. 25-27)
//   update:   S = H P Hᵀ + I,  K = P Hᵀ S⁻¹,  dx = -K r,  P -= K S Kᵀ
// Readings are whitened by σ, so the observation covariance is I. The update
// is applied additively except for the mocap rotation (R <- exp([δ]x) R);
// its covariance stays in the tangent space (the reset Jacobian I - ½[δ]x is
// taken as I, as usual for small updates).
#include "stac/ekf.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <set>

#include "stac/calibrate.hpp"
#include "stac/error.hpp"
#include "stac/frame_jacobian.hpp"
#include "stac/parallel.hpp"
#include "stac/q_phase.hpp"
#include "stac/simulate.hpp"
#include "stac/uncertainty.hpp"

namespace stac {

bool EkfOptions::isValid(std::string* error) const {
  auto fail = [&](const std::string& e) {
    if (error) *error = e;
    return false;
  };
  auto positive = [](double v) { return v > 0 && std::isfinite(v); };
  if (!initial_q.allFinite()) return fail("EKF initial joint angles must be finite");
  if (!positive(initial_q_std) || !positive(solved_q_std_fraction))
    return fail("EKF initial joint-angle std must be positive and finite");
  if (!positive(q_speed)) return fail("EKF joint speed must be positive and finite");
  if (iterations < 1) return fail("EKF iterations must be at least 1");
  if (!(rate_hz >= 0) || !std::isfinite(rate_hz))
    return fail("EKF frame rate must be finite and >= 0 (0: from the log)");
  if (!positive(theta_std_scale) || !positive(rotation_std) || !positive(translation_std) ||
      !positive(marker_std) || !positive(gain_std) || !positive(joint_bias_std) ||
      !positive(tendon_bias_std))
    return fail("EKF seed standard deviations must be positive and finite");
  return true;
}

Eigen::VectorXd firstJointAngles(const Log& log, const RobotModel& robot) {
  const int line = log.header_line;
  std::vector<int> column_of(robot.dof(), -1);
  for (size_t c = 0; c < log.columns.size(); ++c) {
    const std::optional<int> i = robot.qIndex(log.columns[c]);
    if (!i) {
      const std::string why = robot.movableJointIndex(log.columns[c])
                                  ? "' is a mimic follower, not a joint of q"
                                  : "' is not a joint of the robot";
      throw InputError(log.path, line, 0, "joint-angle column '" + log.columns[c] + why);
    }
    column_of[*i] = static_cast<int>(c);
  }
  std::string missing;
  for (int i = 0; i < robot.dof(); ++i)
    if (column_of[i] < 0) missing += (missing.empty() ? "" : ", ") + robot.qName(i);
  if (!missing.empty())
    throw InputError(log.path, line, 0, "joint-angle columns missing for: " + missing);
  if (log.numFrames() == 0) throw InputError(log.path, line, 0, "no joint angles (no data rows)");
  const int row_line = log.line_of_frame.empty() ? line + 1 : log.line_of_frame[0];
  Eigen::VectorXd q(robot.dof());
  for (int i = 0; i < robot.dof(); ++i) {
    q[i] = log.values(0, column_of[i]);
    if (std::isnan(q[i]))
      throw InputError(log.path, row_line, 0,
                       "missing joint angle for " + robot.qName(i) + " (column '" +
                           log.columns[column_of[i]] + "')");
  }
  return q;
}

namespace {

using Clock = std::chrono::steady_clock;

double frameRate(const Observations& obs, double rate_hz) {
  if (rate_hz > 0) return rate_hz;
  std::vector<double> dt;
  for (size_t t = 1; t < obs.time.size(); ++t)
    if (obs.time[t] > obs.time[t - 1]) dt.push_back(obs.time[t] - obs.time[t - 1]);
  if (dt.empty()) return 100.0;
  std::nth_element(dt.begin(), dt.begin() + dt.size() / 2, dt.end());
  return 1.0 / dt[dt.size() / 2];
}

// One standard deviation of the seed per θ entry (EkfOptions).
Eigen::VectorXd seedStd(const MeasurementModel& model, const SensorParameters& seed,
                        const EkfOptions& o) {
  Eigen::VectorXd sd(model.thetaSize());
  sd.segment<3>(MeasurementModel::kRotationOffset).setConstant(o.rotation_std);
  sd.segment<3>(MeasurementModel::kTranslationOffset).setConstant(o.translation_std);
  const SensorSet& s = model.sensors();
  for (size_t m = 0; m < s.markers.size(); ++m)
    sd.segment<3>(model.markerOffset(static_cast<int>(m))).setConstant(o.marker_std);
  for (size_t j = 0; j < s.joint_sensors.size(); ++j) {
    const double g = std::max(std::abs(seed.joint_sensor[j].gain), 1.0);
    sd[model.jointOffset(static_cast<int>(j))] = o.gain_std * g;
    sd[model.jointOffset(static_cast<int>(j)) + 1] = o.joint_bias_std * g;
  }
  for (size_t j = 0; j < s.tendon_sensors.size(); ++j) {
    const double g = std::max(std::abs(seed.tendon_sensor[j].gain), 1.0);
    sd[model.tendonOffset(static_cast<int>(j))] = o.gain_std * g;
    sd[model.tendonOffset(static_cast<int>(j)) + 1] = o.tendon_bias_std * g;
  }
  return sd * o.theta_std_scale;
}

// Adds dθ (free entries only, indexed like `free_index`) to θ.
void applyThetaStep(const MeasurementModel& model, const std::vector<int>& free_index,
                    const Eigen::VectorXd& step, SensorParameters* theta) {
  Eigen::VectorXd full = Eigen::VectorXd::Zero(model.thetaSize());
  for (size_t i = 0; i < free_index.size(); ++i) full[free_index[i]] = step[i];
  const Eigen::Vector3d delta = full.segment<3>(MeasurementModel::kRotationOffset);
  if (delta.norm() > 0)
    theta->mocap.rotation =
        (Eigen::Quaterniond(Eigen::AngleAxisd(delta.norm(), delta.normalized())) *
         theta->mocap.rotation).normalized();
  theta->mocap.translation += full.segment<3>(MeasurementModel::kTranslationOffset);
  const SensorSet& s = model.sensors();
  for (size_t m = 0; m < s.markers.size(); ++m)
    theta->marker_position[m] += full.segment<3>(model.markerOffset(static_cast<int>(m)));
  for (size_t j = 0; j < s.joint_sensors.size(); ++j) {
    const int o = model.jointOffset(static_cast<int>(j));
    theta->joint_sensor[j].gain += full[o];
    theta->joint_sensor[j].bias += full[o + 1];
  }
  for (size_t j = 0; j < s.tendon_sensors.size(); ++j) {
    const int o = model.tendonOffset(static_cast<int>(j));
    theta->tendon_sensor[j].gain += full[o];
    theta->tendon_sensor[j].bias += full[o + 1];
  }
}

double sensorSigma(const NoiseModel& noise, const ReadingJacobian& rj) {
  switch (rj.group) {
    case SensorGroup::kMarker: return noise.marker[rj.sensor];
    case SensorGroup::kJoint: return noise.joint[rj.sensor];
    case SensorGroup::kTendon: return noise.tendon[rj.sensor];
  }
  return 1.0;
}

// Innovation statistics of a stretch of frames, for the progress reports.
struct Stretch {
  double cost = 0;
  double sse[kNumSensorGroups] = {0, 0, 0};
  double count[kNumSensorGroups] = {0, 0, 0};
};

}  // namespace

CalibrationResult calibrateEkf(const RobotModel& robot, const SensorSet& sensors,
                               const SensorParameters& seed, const Observations& obs,
                               const CalibrationOptions& options, RowMatrix* joint_angles) {
  std::string error;
  if (!options.isValid(&error)) throw std::invalid_argument(error);
  const EkfOptions& eo = options.ekf;
  if (obs.num_frames < 1) throw std::invalid_argument("the log has no frames");
  if (eo.initial_q.size() != 0 && eo.initial_q.size() != robot.dof())
    throw std::invalid_argument("EKF initial joint angles: expected " +
                                std::to_string(robot.dof()) + " values");
  const Clock::time_point start = Clock::now();
  const MeasurementModel model(robot, sensors);
  const NoiseModel noise = NoiseModel::fromSeeds(sensors);
  const RobustLoss loss(options.loss, options.loss_scale);
  const int threads = resolveThreads(options.threads);
  std::vector<FrameWorkspace> ws;
  for (int i = 0; i < threads; ++i) ws.emplace_back(model);
  const int T = obs.num_frames;
  const int dof = robot.dof();

  // State layout: free θ entries, then q.
  std::vector<int> free_index;
  for (int i = 0; i < model.thetaSize(); ++i)
    if (model.thetaFree()[i]) free_index.push_back(i);
  const int nf = static_cast<int>(free_index.size());
  const int n = nf + dof;

  SensorParameters theta = seed;
  const std::vector<JointRange> range = motionRanges(robot);
  Eigen::VectorXd span(dof);
  for (int j = 0; j < dof; ++j) span[j] = range[j].upper - range[j].lower;

  // q_0: given (paper §VI-B: the truth), or frame 0 solved at the seed θ.
  Eigen::VectorXd q(dof), q_std(dof);
  if (eo.initial_q.size() == dof) {
    q = eo.initial_q;
    q_std.setConstant(eo.initial_q_std);
  } else {
    QState first;
    first.q = neutralPose(robot).transpose();
    QPhaseOptions qo;
    qo.method = QPhaseMethod::kLmBatch;
    qo.max_steps = 100;
    qo.threads = 1;
    qPhase(model, theta, noise, loss, sliceFrames(obs, 0, 1), qo, &ws, &first);
    q = first.q.row(0).transpose();
    q_std = eo.solved_q_std_fraction * span;
  }
  // Clamp into the limits widened by 5% of the range, as the q-phase does.
  Eigen::VectorXd lower = robot.lowerLimits(), upper = robot.upperLimits();
  for (int j = 0; j < dof; ++j) {
    const double margin = 0.05 * (upper[j] - lower[j]);
    if (std::isfinite(margin)) lower[j] -= margin, upper[j] += margin;
  }
  q = q.cwiseMax(lower).cwiseMin(upper);

  const Eigen::VectorXd theta_std = seedStd(model, seed, eo);
  Eigen::MatrixXd P = Eigen::MatrixXd::Zero(n, n);
  for (int i = 0; i < nf; ++i) P(i, i) = theta_std[free_index[i]] * theta_std[free_index[i]];
  for (int j = 0; j < dof; ++j) P(nf + j, nf + j) = q_std[j] * q_std[j];
  const double dt = 1.0 / frameRate(obs, eo.rate_hz);
  const Eigen::VectorXd process_var = (eo.q_speed * dt * span).array().square();

  CalibrationResult result;
  CalibrationSummary& summary = result.summary;
  summary.method = "ekf";
  summary.frames = T;
  fittedResidualRms(model, seed, noise, loss, obs,
                    q.transpose().replicate(T, 1), threads,
                    summary.before_rms);
  {
    QState s0;
    s0.q = q.transpose().replicate(T, 1);
    summary.initial_cost =
        totalCost(model, seed, noise, loss, obs, EvalOptions(), threads, &ws, &s0);
  }

  RowMatrix filtered(T, dof);
  EvalOptions ev;
  ev.jacobians = true;
  ev.theta_jacobians = true;
  FrameWorkspace& w = ws[0];
  DenseFrame df;
  Eigen::MatrixXd H, PHt, S, K;
  Eigen::VectorXd dx, dx_total;
  Stretch stretch;
  const int report_every = std::max(1, (T + 9) / 10);
  bool finite = true;
  for (int t = 0; t < T; ++t) {
    if (t > 0) P.diagonal().tail(dof) += process_var;
    const double cost = evaluateFrame(model, theta, noise, loss, frameReadings(obs, t), q, ev, &w);
    stretch.cost += cost;
    for (int i = 0; i < w.count; ++i) {
      const ReadingJacobian& rj = w.readings[i];
      const double sigma = sensorSigma(noise, rj);
      stretch.sse[static_cast<int>(rj.group)] += rj.s * sigma * sigma;
      stretch.count[static_cast<int>(rj.group)] += 1;
    }
    // The update; with iterations > 1 the iterated EKF: relinearise at the
    // updated state x_i and redo the update from the prediction x̄,
    //   x_{i+1} = x̄ + K_i (-r_i + H_i (x_i - x̄)),
    // Gauss-Newton on this frame's posterior (the plain EKF is i = 0 only).
    const SensorParameters theta_prior = theta;
    const Eigen::VectorXd q_prior = q;
    dx_total.setZero(n);
    for (int it = 0; it < eo.iterations; ++it) {
      if (it > 0) evaluateFrame(model, theta, noise, loss, frameReadings(obs, t), q, ev, &w);
      denseFrame(model, w, nullptr, &df);
      if (df.rows == 0) break;
      H.resize(df.rows, n);
      for (int i = 0; i < nf; ++i) H.col(i) = df.Jtheta.col(free_index[i]);
      H.rightCols(dof) = df.Jq;
      PHt.noalias() = P * H.transpose();
      S.noalias() = H * PHt;
      S.diagonal().array() += 1.0;
      Eigen::LLT<Eigen::MatrixXd> llt(S);
      K = llt.solve(PHt.transpose()).transpose();  // P Hᵀ S⁻¹ (S symmetric)
      dx.noalias() = K * (H * dx_total - df.r);
      if (!dx.allFinite() || llt.info() != Eigen::Success) {
        finite = false;
        break;
      }
      const double change = (dx - dx_total).norm();
      theta = theta_prior;
      applyThetaStep(model, free_index, dx.head(nf), &theta);
      q = (q_prior + dx.tail(dof)).cwiseMax(lower).cwiseMin(upper);
      dx_total = dx;
      dx_total.tail(dof) = q - q_prior;
      if (it + 1 == eo.iterations || change < 1e-10 * (1.0 + dx.norm())) {
        P.noalias() -= K * PHt.transpose();
        P = 0.5 * (P + P.transpose()).eval();
        break;
      }
    }
    if (!finite || !P.allFinite()) {
      finite = false;
      filtered.bottomRows(T - t).rowwise() = q.transpose();
      break;
    }
    filtered.row(t) = q.transpose();
    if (options.progress && ((t + 1) % report_every == 0 || t + 1 == T)) {
      IterationReport r;
      r.iteration = (t + report_every) / report_every;
      r.cost = stretch.cost;
      for (int g = 0; g < kNumSensorGroups; ++g) {
        r.present[g] = stretch.count[g] > 0;
        r.rms[g] = stretch.count[g] > 0 ? std::sqrt(stretch.sse[g] / stretch.count[g]) : 0.0;
      }
      r.elapsed = std::chrono::duration<double>(Clock::now() - start).count();
      r.stage = "ekf";
      options.progress(r);
      stretch = Stretch();
    }
  }

  // Uncertainty: the filter's own covariance, except that directions the
  // data cannot determine (at the final θ and the filtered q_t) are listed
  // and get an infinite std rather than the prior's.
  Eigen::VectorXd std_full = Eigen::VectorXd::Zero(model.thetaSize());
  for (int i = 0; i < nf; ++i) std_full[free_index[i]] = std::sqrt(std::max(P(i, i), 0.0));
  const UncertaintyResult unc =
      estimateUncertainty(model, theta, noise, loss, obs, filtered, threads, &ws);
  std::set<std::string> unidentified;
  for (const UnidentifiableDirection& d : unc.unidentifiable)
    unidentified.insert(d.parameters.begin(), d.parameters.end());
  for (int i = 0; i < model.thetaSize(); ++i)
    if (unidentified.count(model.thetaNames()[i]))
      std_full[i] = std::numeric_limits<double>::infinity();

  result.sensors = sensors;
  result.theta = theta;
  result.std = toParameterStd(model, std_full);
  residualStatistics(model, theta, obs, filtered, threads, &result);
  summary.iterations = 1;  // one forward pass
  summary.converged = finite;
  QState fin;
  fin.q = filtered;
  summary.final_cost = totalCost(model, theta, noise, loss, obs, EvalOptions(), threads, &ws, &fin);
  auto group_rms = [](const std::vector<ResidualStats>& v) {
    double sse = 0, count = 0;
    for (const ResidualStats& r : v) sse += r.rms * r.rms * r.count, count += r.count;
    return count > 0 ? std::sqrt(sse / count) : 0.0;
  };
  summary.after_rms[0] = group_rms(result.marker_residual);
  summary.after_rms[1] = group_rms(result.joint_residual);
  summary.after_rms[2] = group_rms(result.tendon_residual);
  summary.unidentifiable = unc.unidentifiable;
  summariseGroupNoise(sensors, noise, &summary);
  summary.wall_time = std::chrono::duration<double>(Clock::now() - start).count();
  if (joint_angles) *joint_angles = filtered;
  return result;
}

}  // namespace stac
