// The STAC alternation (paper §II-C, §III-D, §III-E) and the calibration
// driver shared with the monolithic mode.
//
// Wide basin. Real seeds are poor (any mocap rotation, gains of either sign,
// unknown biases, markers at link origins), so before alternating on
// everything we let the markers, whose model has no unknown scale, lead:
//  1. Procrustes of the measured marker cloud against the one predicted at
//     the neutral pose, then averaging of the marker positions (closed
//     forms, eq. 13-17);
//  2. a marker-only alternation (q-phase on markers, θ-phase on the marker
//     group), so each q_t follows the markers;
//  3. a θ-phase of the joint and tendon sensors against those q_t (linear
//     least squares: any sign of gain, any bias).
// Then the full alternation with per-group variance adaptation, which keeps
// badly fitting groups from dominating while they are still wrong.
#include "stac/calibrate.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <cstdio>
#include <cstdlib>

#include "stac/classical.hpp"
#include "stac/parallel.hpp"
#include "stac/schur.hpp"
#include "stac/theta_phase.hpp"
#include "stac/uncertainty.hpp"
#include "wide_basin.hpp"

namespace stac {

// Implemented in joint_solver.cpp.
void solveJointProblem(const MeasurementModel& model, const NoiseModel& noise,
                       const RobustLoss& loss, const Observations& obs,
                       const CalibrationOptions& options, SensorParameters* theta,
                       QState* state, int* iterations, bool* converged);

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

Eigen::VectorXd neutralPose(const RobotModel& robot) {
  Eigen::VectorXd q = Eigen::VectorXd::Zero(robot.dof());
  for (int i = 0; i < robot.dof(); ++i)
    q[i] = std::clamp(0.0, robot.lowerLimits()[i], robot.upperLimits()[i]);
  return q;
}

namespace {

using Clock = std::chrono::steady_clock;

// One pass over all frames: cost, raw residual sums per group and, for the
// variance adaptation, the degrees of freedom each group's residuals lost to
// the fitted q_t (the leverage Σ tr(J_g H⁻¹ J_gᵀ)).
struct PassStats {
  double cost = 0;
  double sse[kNumSensorGroups] = {0, 0, 0};      // raw units²
  double count[kNumSensorGroups] = {0, 0, 0};    // readings
  double wsse[kNumSensorGroups] = {0, 0, 0};     // Σ w s (seed-whitened)
  double wdims[kNumSensorGroups] = {0, 0, 0};    // Σ w rows
  double leverage[kNumSensorGroups] = {0, 0, 0};
};

PassStats costPass(const MeasurementModel& model, const SensorParameters& theta,
                   const NoiseModel& noise, const NoiseModel& seed_noise,
                   const RobustLoss& loss, const Observations& obs, const RowMatrix& q,
                   bool leverage, int threads, std::vector<FrameWorkspace>* ws) {
  const int T = obs.num_frames;
  const int dof = model.dof();
  std::vector<PassStats> chunk_stats(numChunks(T));
  EvalOptions eo;
  eo.jacobians = leverage;
  parallelFor(numChunks(T), threads, [&](int chunk, int tid) {
    FrameWorkspace& w = (*ws)[tid];
    PassStats& st = chunk_stats[chunk];
    Eigen::VectorXd qt(dof), g(dof);
    Eigen::MatrixXd H(dof, dof), Hinv(dof, dof);
    const int end = std::min(T, (chunk + 1) * kFramesPerChunk);
    for (int t = chunk * kFramesPerChunk; t < end; ++t) {
      qt = q.row(t).transpose();
      st.cost += evaluateFrame(model, theta, noise, loss, frameReadings(obs, t), qt, eo, &w);
      if (leverage) {
        accumulateNormalEquations(w, &H, &g);
        H.diagonal().array() += 1e-12 * std::max(1.0, H.diagonal().maxCoeff());
        Hinv = H.llt().solve(Eigen::MatrixXd::Identity(dof, dof));
      }
      for (int i = 0; i < w.count; ++i) {
        const ReadingJacobian& rj = w.readings[i];
        const int g_idx = static_cast<int>(rj.group);
        const double sigma =
            rj.group == SensorGroup::kMarker  ? noise.marker[rj.sensor]
            : rj.group == SensorGroup::kJoint ? noise.joint[rj.sensor]
                                              : noise.tendon[rj.sensor];
        const double seed_sigma =
            rj.group == SensorGroup::kMarker  ? seed_noise.marker[rj.sensor]
            : rj.group == SensorGroup::kJoint ? seed_noise.joint[rj.sensor]
                                              : seed_noise.tendon[rj.sensor];
        st.sse[g_idx] += rj.s * sigma * sigma;
        st.count[g_idx] += 1;
        const double ratio = sigma / seed_sigma;
        st.wsse[g_idx] += rj.weight * rj.s * ratio * ratio;
        st.wdims[g_idx] += rj.weight * rj.rows;
        if (leverage) {
          // This reading's share of the dof the frame's q_t took:
          // tr(J H⁻¹ Jᵀ) over its (few) columns.
          const std::vector<int>& cols = *rj.q_cols;
          const int k = static_cast<int>(cols.size());
          for (int r = 0; r < rj.rows; ++r)
            for (int a = 0; a < k; ++a)
              for (int b = 0; b < k; ++b)
                st.leverage[g_idx] += rj.Jq(r, a) * Hinv(cols[a], cols[b]) * rj.Jq(r, b);
        }
      }
    }
  });
  PassStats total;
  for (const PassStats& s : chunk_stats) {
    total.cost += s.cost;
    for (int g = 0; g < kNumSensorGroups; ++g) {
      total.sse[g] += s.sse[g];
      total.count[g] += s.count[g];
      total.wsse[g] += s.wsse[g];
      total.wdims[g] += s.wdims[g];
      total.leverage[g] += s.leverage[g];
    }
  }
  return total;
}

// Re-estimates one scale per sensor group (paper §III-E); returns the
// largest relative change.
double adaptNoise(const PassStats& st, const NoiseModel& seed, double kappa[3],
                  NoiseModel* noise) {
  double change = 0;
  for (int g = 0; g < kNumSensorGroups; ++g) {
    const double dofs = st.wdims[g] - st.leverage[g];
    if (st.count[g] == 0 || dofs <= 0.5) continue;
    const double k2 = st.wsse[g] / dofs;
    const double k = std::max(std::sqrt(k2), 1e-9);
    change = std::max(change, std::abs(k - kappa[g]) / kappa[g]);
    kappa[g] = k;
  }
  noise->marker = seed.marker;
  noise->joint = seed.joint;
  noise->tendon = seed.tendon;
  for (double& s : noise->marker) s *= kappa[0];
  for (double& s : noise->joint) s *= kappa[1];
  for (double& s : noise->tendon) s *= kappa[2];
  return change;
}

IterationReport makeReport(int it, const PassStats& st, Clock::time_point start,
                           const std::string& stage, const SensorParameters* theta = nullptr) {
  IterationReport r;
  r.theta = theta;
  r.iteration = it;
  r.cost = st.cost;
  for (int g = 0; g < kNumSensorGroups; ++g) {
    r.present[g] = st.count[g] > 0;
    r.rms[g] = st.count[g] > 0 ? std::sqrt(st.sse[g] / st.count[g]) : 0.0;
  }
  r.elapsed = std::chrono::duration<double>(Clock::now() - start).count();
  r.stage = stage;
  return r;
}

std::string sensorName(const SensorSet& s, SensorGroup g, int i) {
  switch (g) {
    case SensorGroup::kMarker: return s.markers[i].name;
    case SensorGroup::kJoint: return s.joint_sensors[i].name;
    case SensorGroup::kTendon: return s.tendon_sensors[i].name;
  }
  return "";
}

// The readings the robust loss trusted least.
std::vector<DownweightedReading> downweighted(const MeasurementModel& model,
                                              const SensorParameters& theta,
                                              const NoiseModel& noise,
                                              const RobustLoss& loss,
                                              const Observations& obs, const RowMatrix& q,
                                              int max_count, int threads,
                                              std::vector<FrameWorkspace>* ws) {
  std::vector<DownweightedReading> all;
  if (!loss.enabled() || max_count <= 0) return all;
  const int T = obs.num_frames;
  std::vector<std::vector<DownweightedReading>> per_chunk(numChunks(T));
  EvalOptions eo;
  eo.jacobians = false;
  parallelFor(numChunks(T), threads, [&](int chunk, int tid) {
    FrameWorkspace& w = (*ws)[tid];
    Eigen::VectorXd qt(model.dof());
    const int end = std::min(T, (chunk + 1) * kFramesPerChunk);
    for (int t = chunk * kFramesPerChunk; t < end; ++t) {
      qt = q.row(t).transpose();
      evaluateFrame(model, theta, noise, loss, frameReadings(obs, t), qt, eo, &w);
      for (int i = 0; i < w.count; ++i) {
        const ReadingJacobian& rj = w.readings[i];
        if (rj.weight < 0.999)
          per_chunk[chunk].push_back(
              {t, sensorName(model.sensors(), rj.group, rj.sensor), rj.weight});
      }
    }
  });
  for (auto& c : per_chunk) all.insert(all.end(), c.begin(), c.end());
  std::stable_sort(all.begin(), all.end(), [](const auto& a, const auto& b) {
    return a.weight < b.weight;
  });
  if (static_cast<int>(all.size()) > max_count) all.resize(max_count);
  return all;
}


}  // namespace

void residualStatistics(const MeasurementModel& model, const SensorParameters& theta,
                        const Observations& obs, const RowMatrix& q, int threads,
                        CalibrationResult* result) {
  const SensorSet& s = model.sensors();
  const int M = static_cast<int>(s.markers.size());
  const int J = static_cast<int>(s.joint_sensors.size());
  const int N = static_cast<int>(s.tendon_sensors.size());
  const int T = obs.num_frames;
  // Per chunk: for each sensor sum of e², sum of |e|, count.
  const int n = M + J + N;
  std::vector<Eigen::MatrixXd> acc(numChunks(T), Eigen::MatrixXd::Zero(n, 3));
  const int th = resolveThreads(threads);
  std::vector<KinematicsWorkspace> kin(th, KinematicsWorkspace(model.robot()));
  parallelFor(numChunks(T), th, [&](int chunk, int tid) {
    Eigen::VectorXd qt(model.dof()), pm(3 * M), pj(J), pt(N);
    const int end = std::min(T, (chunk + 1) * kFramesPerChunk);
    for (int t = chunk * kFramesPerChunk; t < end; ++t) {
      qt = q.row(t).transpose();
      predictFrame(model, theta, qt, &kin[tid], pm.data(), pj.data(), pt.data());
      auto add = [&](int i, double e) {
        acc[chunk](i, 0) += e * e;
        acc[chunk](i, 1) += std::abs(e);
        acc[chunk](i, 2) += 1;
      };
      for (int m = 0; m < M; ++m) {
        const double* x = obs.marker.row(t).data() + 3 * m;
        if (std::isnan(x[0])) continue;
        add(m, (pm.segment<3>(3 * m) - Eigen::Vector3d(x[0], x[1], x[2])).norm());
      }
      for (int j = 0; j < J; ++j)
        if (!std::isnan(obs.joint(t, j))) add(M + j, pj[j] - obs.joint(t, j));
      for (int k = 0; k < N; ++k)
        if (!std::isnan(obs.tendon(t, k))) add(M + J + k, pt[k] - obs.tendon(t, k));
    }
  });
  Eigen::MatrixXd total = Eigen::MatrixXd::Zero(n, 3);
  for (const auto& a : acc) total += a;
  auto stats = [&](int i) {
    ResidualStats r;
    r.count = static_cast<int>(total(i, 2));
    if (r.count > 0) {
      r.rms = std::sqrt(total(i, 0) / r.count);
      r.mae = total(i, 1) / r.count;
    }
    return r;
  };
  result->marker_residual.clear();
  result->joint_residual.clear();
  result->tendon_residual.clear();
  for (int m = 0; m < M; ++m) result->marker_residual.push_back(stats(m));
  for (int j = 0; j < J; ++j) result->joint_residual.push_back(stats(M + j));
  for (int k = 0; k < N; ++k) result->tendon_residual.push_back(stats(M + J + k));
}

void summariseGroupNoise(const SensorSet& sensors, const NoiseModel& noise,
                         CalibrationSummary* summary, const std::vector<bool>* skip_joint) {
  auto rms = [](const std::vector<double>& v, const std::vector<bool>* skip) {
    double s = 0;
    int n = 0;
    for (size_t i = 0; i < v.size(); ++i)
      if (!skip || !(*skip)[i]) s += v[i] * v[i], ++n;
    return n == 0 ? 0.0 : std::sqrt(s / n);
  };
  summary->group_present[0] = !sensors.markers.empty();
  summary->group_present[1] = !sensors.joint_sensors.empty();
  summary->group_present[2] = !sensors.tendon_sensors.empty();
  summary->group_sigma[0] = rms(noise.marker, nullptr);
  summary->group_sigma[1] = rms(noise.joint, skip_joint);
  summary->group_sigma[2] = rms(noise.tendon, nullptr);
}

void fittedResidualRms(const MeasurementModel& model, const SensorParameters& theta,
                       const NoiseModel& noise, const RobustLoss& loss, const Observations& obs,
                       const RowMatrix& q_start, int threads, double rms[kNumSensorGroups]) {
  threads = resolveThreads(threads);
  std::vector<FrameWorkspace> ws;
  for (int i = 0; i < threads; ++i) ws.emplace_back(model);
  const std::vector<int> sub = spreadFrames(obs.num_frames, kInitFrames);
  const Observations sub_obs = selectFrames(obs, sub);
  QState seed_state;
  seed_state.q = RowMatrix(sub_obs.num_frames, model.dof());
  for (int k = 0; k < sub_obs.num_frames; ++k) seed_state.q.row(k) = q_start.row(sub[k]);
  QPhaseOptions qo;
  qo.method = QPhaseMethod::kLmBatch;
  qo.max_steps = 10;
  qo.threads = threads;
  qPhase(model, theta, noise, loss, sub_obs, qo, &ws, &seed_state);
  const PassStats before = costPass(model, theta, noise, NoiseModel::fromSeeds(model.sensors()),
                                    loss, sub_obs, seed_state.q, false, threads, &ws);
  for (int g = 0; g < kNumSensorGroups; ++g)
    rms[g] = before.count[g] > 0 ? std::sqrt(before.sse[g] / before.count[g]) : 0;
}

CalibrationResult calibrate(const RobotModel& robot, const SensorSet& sensors,
                            const SensorParameters& seed, const Observations& obs,
                            const CalibrationOptions& options, RowMatrix* joint_angles,
                            const RowMatrix* q0) {
  std::string error;
  if (!options.isValid(&error)) throw std::invalid_argument(error);
  if (obs.num_frames < 1) throw std::invalid_argument("the log has no frames");
  // The baselines (ekf.hpp, classical.hpp).
  if (options.method == Method::kEkf) {
    if (!q0 || options.ekf.initial_q.size() != 0)
      return calibrateEkf(robot, sensors, seed, obs, options, joint_angles);
    CalibrationOptions with_q0 = options;
    with_q0.ekf.initial_q = q0->row(0).transpose();
    return calibrateEkf(robot, sensors, seed, obs, with_q0, joint_angles);
  }
  if (options.method == Method::kClassical)
    return calibrateClassical(robot, sensors, seed, obs, options, joint_angles);
  const Clock::time_point start = Clock::now();
  const MeasurementModel model(robot, sensors);
  const NoiseModel seed_noise = NoiseModel::fromSeeds(sensors);
  NoiseModel noise = seed_noise;
  double kappa[kNumSensorGroups] = {1, 1, 1};
  const RobustLoss loss(options.loss, options.loss_scale);
  const int threads = resolveThreads(options.threads);
  std::vector<FrameWorkspace> ws;
  for (int i = 0; i < threads; ++i) ws.emplace_back(model);

  QState state;
  if (q0) {
    if (q0->rows() != obs.num_frames || q0->cols() != robot.dof())
      throw std::invalid_argument("initial joint angles have the wrong shape");
    state.q = *q0;
  } else {
    state.q = neutralPose(robot).transpose().replicate(obs.num_frames, 1);
  }
  SensorParameters theta = seed;

  CalibrationResult result;
  CalibrationSummary& summary = result.summary;
  summary.method = options.method == Method::kStac ? "stac" : "joint";
  summary.frames = obs.num_frames;
  fittedResidualRms(model, theta, noise, loss, obs, state.q, threads, summary.before_rms);
  PassStats st = costPass(model, theta, noise, seed_noise, loss, obs, state.q, false,
                          threads, &ws);
  summary.initial_cost = st.cost;

  const bool has_markers = !sensors.markers.empty();
  if (options.wide_basin_init && has_markers && !q0) {
    // Wide-basin initialisation on at most kInitFrames frames spread over
    // the log (wide_basin.cpp), then every frame's q_t from the nearest
    // initialised frame by LM to convergence.
    const std::vector<int> sub = spreadFrames(obs.num_frames, kInitFrames);
    const Observations sub_obs = selectFrames(obs, sub);
    QState sub_state;
    sub_state.q = neutralPose(robot).transpose().replicate(sub_obs.num_frames, 1);
    theta = wideBasinInitialisation(model, sub_obs, noise, loss, threads, &ws, theta, &sub_state,
                                    options.coupled_steps);
    for (int t = 0, k = 0; t < obs.num_frames; ++t) {
      while (k + 1 < static_cast<int>(sub.size()) && std::abs(sub[k + 1] - t) <= std::abs(sub[k] - t)) ++k;
      state.q.row(t) = sub_state.q.row(k);
    }
    QPhaseOptions qo;
    qo.method = QPhaseMethod::kLmBatch;
    qo.max_steps = 6;
    qo.threads = threads;
    qPhase(model, theta, noise, loss, obs, qo, &ws, &state);
    st = costPass(model, theta, noise, seed_noise, loss, obs, state.q, options.adapt_variance,
                  threads, &ws);
    if (options.adapt_variance) {
      adaptNoise(st, seed_noise, kappa, &noise);
      st = costPass(model, theta, noise, seed_noise, loss, obs, state.q, false, threads, &ws);
    }
    if (options.progress) options.progress(makeReport(0, st, start, "init", &theta));
  } else if (options.progress) {
    options.progress(makeReport(0, st, start, "seed", &theta));
  }

  int iterations = 0;
  bool converged = false;
  if (options.method == Method::kJoint) {
    // Variance adaptation around the monolithic solve: solve, re-estimate σ,
    // solve again until σ settles.
    for (int round = 0; round < (options.adapt_variance ? 5 : 1); ++round) {
      int its = 0;
      solveJointProblem(model, noise, loss, obs, options, &theta, &state, &its, &converged);
      iterations += its;
      st = costPass(model, theta, noise, seed_noise, loss, obs, state.q,
                    options.adapt_variance, threads, &ws);
      if (options.progress) options.progress(makeReport(round + 1, st, start, "joint", &theta));
      if (!options.adapt_variance) break;
      const double change = adaptNoise(st, seed_noise, kappa, &noise);
      st = costPass(model, theta, noise, seed_noise, loss, obs, state.q, false, threads, &ws);
      if (change < 1e-4) break;
    }
  } else {
    QPhaseOptions qo;
    qo.method = options.q_phase;
    qo.threads = threads;
    ThetaPhaseOptions to;
    to.threads = threads;
    double cost = st.cost;
    double lambda = 1e-4;
    // The alternation until it stalls; then coupled Gauss-Newton steps
    // (every q_t eliminated per frame, schur.hpp), which converge fast where
    // q and θ are strongly coupled and the alternation would crawl.
    bool coupled = false;
    for (int it = 1; it <= options.max_iterations; ++it) {
      if (coupled) {
        coupledStep(model, noise, loss, obs, threads, &ws, &lambda, &theta, &state);
      } else {
        qPhase(model, theta, noise, loss, obs, qo, &ws, &state);
        thetaPhase(model, noise, loss, obs, state, to, &ws, &theta);
      }
      st = costPass(model, theta, noise, seed_noise, loss, obs, state.q,
                    options.adapt_variance, threads, &ws);
      const double rel = (cost - st.cost) / std::max(cost, 1e-300);
      if (options.coupled_steps && rel < 1e-2) coupled = true;
      iterations = it;
      double change = 0;
      if (options.progress) options.progress(makeReport(it, st, start, "stac", &theta));
      if (options.adapt_variance) {
        change = adaptNoise(st, seed_noise, kappa, &noise);
        st = costPass(model, theta, noise, seed_noise, loss, obs, state.q, false, threads, &ws);
      }
      cost = st.cost;
      if (std::abs(rel) < options.tolerance && change < 1e-3) {
        converged = true;
        break;
      }
    }
  }

  // Uncertainty at the optimum, with the final σ.
  const UncertaintyResult unc =
      estimateUncertainty(model, theta, noise, loss, obs, state.q, threads, &ws);
  result.sensors = sensors;
  for (size_t m = 0; m < sensors.markers.size(); ++m) result.sensors.markers[m].sigma = noise.marker[m];
  for (size_t j = 0; j < sensors.joint_sensors.size(); ++j)
    result.sensors.joint_sensors[j].sigma = noise.joint[j];
  for (size_t j = 0; j < sensors.tendon_sensors.size(); ++j)
    result.sensors.tendon_sensors[j].sigma = noise.tendon[j];
  if (!sensors.markers.empty()) result.sensors.mocap_sigma = sensors.mocap_sigma * kappa[0];
  result.theta = theta;
  result.std = toParameterStd(model, unc.std);
  residualStatistics(model, theta, obs, state.q, threads, &result);
  summary.iterations = iterations;
  summary.converged = converged;
  summary.final_cost = st.cost;
  for (int g = 0; g < kNumSensorGroups; ++g)
    summary.after_rms[g] = st.count[g] > 0 ? std::sqrt(st.sse[g] / st.count[g]) : 0;
  summary.unidentifiable = unc.unidentifiable;
  summary.downweighted = downweighted(model, theta, noise, loss, obs, state.q,
                                      options.max_downweighted, threads, &ws);
  summariseGroupNoise(sensors, noise, &summary);
  summary.wall_time = std::chrono::duration<double>(Clock::now() - start).count();
  if (joint_angles) *joint_angles = state.q;
  return result;
}

}  // namespace stac
