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
#include <array>
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
#include "methods/wide_basin.hpp"

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

// Outer iterations at most on the initial subsample of a long log.
constexpr int kPresolveIterations = 40;

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
  double group_cost[kNumSensorGroups] = {0, 0, 0};  // ½ Σ ρ per group
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
    Eigen::MatrixXd H(dof, dof), Linv(dof, dof);
    const int end = std::min(T, (chunk + 1) * kFramesPerChunk);
    for (int t = chunk * kFramesPerChunk; t < end; ++t) {
      qt = q.row(t).transpose();
      st.cost += evaluateFrame(model, theta, noise, loss, frameReadings(obs, t), qt, eo, &w);
      int rows = 0;
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
        st.group_cost[g_idx] += 0.5 * rj.rho;
        rows += rj.rows;
      }
      if (!leverage || rows == 0) continue;
      accumulateNormalEquations(w, &H, &g);
      addGroupLeverage(w, &H, &Linv, st.leverage);
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
      total.group_cost[g] += s.group_cost[g];
    }
  }
  return total;
}

// One scale per sensor group on the seed σ's (paper §III-E), and the last
// plain update of each, for the extrapolation in adaptNoise.
struct GroupScales {
  double kappa[kNumSensorGroups] = {1, 1, 1};
  double last_step[kNumSensorGroups] = {0, 0, 0};
};

// Re-estimates each group's scale; returns the largest relative change.
// The re-estimate is a fixed-point iteration (the fit, and so the residuals
// and the dof the q_t took, follow σ) that contracts slowly, by about half
// per iteration when pots carry most of their joints' information: when two
// plain updates of a group shrink geometrically, jump to the limit of that
// geometric series (Aitken's Δ²), then take a plain update again.
double adaptNoise(const PassStats& st, const NoiseModel& seed, GroupScales* scales,
                  NoiseModel* noise) {
  double change = 0;
  for (int g = 0; g < kNumSensorGroups; ++g) {
    const double dofs = st.wdims[g] - st.leverage[g];
    if (st.count[g] == 0 || dofs <= 0.5) continue;
    double& kappa = scales->kappa[g];
    double& last = scales->last_step[g];
    const double k = std::max(std::sqrt(st.wsse[g] / dofs), 1e-9);
    const double step = k - kappa;
    const double ratio = last != 0 ? step / last : 0;
    double next = k;
    // Only on clear trends (small steps mix in the fit's own settling), and
    // never far from the plain estimate: far from the optimum the "trend"
    // may be the fit changing basin, not σ converging.
    if (ratio > 0 && ratio < 0.9 && std::abs(step) > 1e-3 * kappa) {
      next = std::clamp(kappa + step / (1 - std::min(ratio, 0.6)), 0.8 * k, 1.25 * k);
      last = 0;
    } else {
      last = step;
    }
    change = std::max(change, std::abs(next - kappa) / kappa);
    kappa = next;
  }
  noise->marker = seed.marker;
  noise->joint = seed.joint;
  noise->tendon = seed.tendon;
  for (double& s : noise->marker) s *= scales->kappa[0];
  for (double& s : noise->joint) s *= scales->kappa[1];
  for (double& s : noise->tendon) s *= scales->kappa[2];
  return change;
}

// adaptNoise, then *st scored again at the new σ. Without a robust loss
// each group's whitened squares scale by (κ_old / κ_new)², so no pass over
// the frames is needed.
double adaptAndRescore(const MeasurementModel& model, const SensorParameters& theta,
                       const NoiseModel& seed_noise, const RobustLoss& loss,
                       const Observations& obs, const RowMatrix& q, int threads,
                       std::vector<FrameWorkspace>* ws, GroupScales* scales, NoiseModel* noise,
                       PassStats* st) {
  const GroupScales before = *scales;
  const double change = adaptNoise(*st, seed_noise, scales, noise);
  if (loss.enabled()) {
    *st = costPass(model, theta, *noise, seed_noise, loss, obs, q, false, threads, ws);
    return change;
  }
  st->cost = 0;
  for (int g = 0; g < kNumSensorGroups; ++g) {
    const double r = before.kappa[g] / scales->kappa[g];
    st->group_cost[g] *= r * r;
    st->cost += st->group_cost[g];
    st->leverage[g] = 0;
  }
  return change;
}

// A pass at the current σ; with `adapt`, σ re-estimated from it and the
// pass re-scored at the new σ.
PassStats adaptedPass(const MeasurementModel& model, const SensorParameters& theta,
                      const NoiseModel& seed_noise, const RobustLoss& loss,
                      const Observations& obs, const RowMatrix& q, bool adapt, int threads,
                      std::vector<FrameWorkspace>* ws, GroupScales* scales, NoiseModel* noise) {
  PassStats st = costPass(model, theta, *noise, seed_noise, loss, obs, q, adapt, threads, ws);
  if (adapt)
    adaptAndRescore(model, theta, seed_noise, loss, obs, q, threads, ws, scales, noise, &st);
  return st;
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

struct LoopOutcome {
  PassStats st;
  int iterations = 0;
  bool converged = false;
};

// The STAC alternation with per-group variance adaptation, from `st` (the
// last pass at the current σ), until the relative cost decrease is below
// `tolerance` and σ has settled. Once the alternation stalls (or from the
// start with `coupled`), coupled Gauss-Newton steps (every q_t eliminated
// per frame, schur.hpp), which converge fast where q and θ are strongly
// coupled and the alternation would crawl. `report` sees every iteration.
LoopOutcome stacIterations(const MeasurementModel& model, const Observations& obs,
                           const NoiseModel& seed_noise, const RobustLoss& loss,
                           const CalibrationOptions& options, bool coupled, PassStats st,
                           GroupScales* kappa, NoiseModel* noise,
                           SensorParameters* theta, QState* state,
                           std::vector<FrameWorkspace>* ws,
                           const std::function<void(int, const PassStats&)>& report) {
  const int threads = resolveThreads(options.threads);
  QPhaseOptions qo;
  qo.method = options.q_phase;
  qo.threads = threads;
  ThetaPhaseOptions to;
  to.threads = threads;
  double cost = st.cost;
  double lambda = 1e-4;
  LoopOutcome out;
  for (int it = 1; it <= options.max_iterations; ++it) {
    if (coupled) {
      // The step's own pass over the frames at its start measures the dof
      // the q_t take for the variance adaptation, which saves a pass with
      // Jacobians; at the fixed point start and end coincide.
      std::vector<std::array<double, kNumSensorGroups>> lev(kReductionBlocks, {0, 0, 0});
      std::vector<Eigen::MatrixXd> H(kReductionBlocks), Linv(kReductionBlocks);  // scratch
      const FrameVisitor visit = [&](int block, const FrameWorkspace& w,
                                     const Eigen::MatrixXd& Hqq) {
        H[block] = Hqq;
        Linv[block].resize(Hqq.rows(), Hqq.cols());
        addGroupLeverage(w, &H[block], &Linv[block], lev[block].data());
      };
      coupledStep(model, *noise, loss, obs, threads, ws, &lambda, theta, state, EvalOptions(),
                  false, options.adapt_variance ? visit : FrameVisitor());
      st = costPass(model, *theta, *noise, seed_noise, loss, obs, state->q, false, threads, ws);
      for (const auto& block : lev)
        for (int g = 0; g < kNumSensorGroups; ++g) st.leverage[g] += block[g];
    } else {
      qPhase(model, *theta, *noise, loss, obs, qo, ws, state);
      thetaPhase(model, *noise, loss, obs, *state, to, ws, theta);
      st = costPass(model, *theta, *noise, seed_noise, loss, obs, state->q,
                    options.adapt_variance, threads, ws);
    }
    const double rel = (cost - st.cost) / std::max(cost, 1e-300);
    if (options.coupled_steps && rel < 1e-2) coupled = true;
    out.iterations = it;
    double change = 0;
    if (report) report(it, st);
    if (options.adapt_variance) {
      change = adaptAndRescore(model, *theta, seed_noise, loss, obs, state->q, threads, ws,
                               kappa, noise, &st);
      // The first update of a run also absorbs the change of data or start
      // point: not a step of the geometric trend the extrapolation assumes.
      if (it == 1) std::fill(kappa->last_step, kappa->last_step + kNumSensorGroups, 0.0);
    }
    cost = st.cost;
    if (std::abs(rel) < options.tolerance && change < 1e-3) {
      out.converged = true;
      break;
    }
  }
  out.st = st;
  return out;
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
  GroupScales kappa;
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
  bool start_coupled = false, presolved = false;
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
    if (options.method == Method::kStac && sub_obs.num_frames < obs.num_frames) {
      // Converge on the subsample first (θ and σ): each iteration there
      // costs a fraction of one on the whole log, which then needs only the
      // last few coupled steps.
      const PassStats sub_st =
          adaptedPass(model, theta, seed_noise, loss, sub_obs, sub_state.q,
                      options.adapt_variance, threads, &ws, &kappa, &noise);
      // Only a start: a subsample that does not settle within
      // kPresolveIterations hands over what it has.
      CalibrationOptions sub_options = options;
      sub_options.max_iterations = std::min(options.max_iterations, kPresolveIterations);
      presolved = true;
      start_coupled = options.coupled_steps &&
                      stacIterations(model, sub_obs, seed_noise, loss, sub_options, false, sub_st,
                                     &kappa, &noise, &theta, &sub_state, &ws, nullptr)
                          .converged;
    }
    // Every other frame's q_t from its initialised neighbours (linearly in
    // between; the nearer one where a joint jumps, e.g. a continuous joint
    // a turn apart), then polished by a few LM steps.
    for (int t = 0, k = 0; t < obs.num_frames; ++t) {
      while (k + 1 < static_cast<int>(sub.size()) && sub[k + 1] <= t) ++k;
      const bool between = t > sub[k] && k + 1 < static_cast<int>(sub.size());
      const double f = between ? static_cast<double>(t - sub[k]) / (sub[k + 1] - sub[k]) : 0.0;
      for (int j = 0; j < robot.dof(); ++j) {
        const double a = sub_state.q(k, j);
        const double b = between ? sub_state.q(k + 1, j) : a;
        state.q(t, j) = std::abs(b - a) < 0.5 ? a + f * (b - a) : (f < 0.5 ? a : b);
      }
    }
    QPhaseOptions qo;
    qo.method = QPhaseMethod::kLmBatch;
    qo.max_steps = 3;
    qo.threads = threads;
    qPhase(model, theta, noise, loss, obs, qo, &ws, &state);
    // σ was adapted on the subsample when it was solved first; else here.
    st = adaptedPass(model, theta, seed_noise, loss, obs, state.q,
                     options.adapt_variance && !presolved, threads, &ws, &kappa, &noise);
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
      const double change = adaptAndRescore(model, theta, seed_noise, loss, obs, state.q,
                                            threads, &ws, &kappa, &noise, &st);
      if (change < 1e-4) break;
    }
  } else {
    const LoopOutcome out = stacIterations(
        model, obs, seed_noise, loss, options, start_coupled, st, &kappa, &noise, &theta, &state,
        &ws, [&](int it, const PassStats& s) {
          if (options.progress) options.progress(makeReport(it, s, start, "stac", &theta));
        });
    st = out.st;
    iterations = out.iterations;
    converged = out.converged;
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
  if (!sensors.markers.empty()) result.sensors.mocap_sigma = sensors.mocap_sigma * kappa.kappa[0];
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
