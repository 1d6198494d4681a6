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

#include "stac/parallel.hpp"
#include "stac/schur.hpp"
#include "stac/theta_phase.hpp"
#include "stac/uncertainty.hpp"

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
    Eigen::VectorXd qt(dof), g(dof), col(dof);
    Eigen::MatrixXd H(dof, dof);
    const int end = std::min(T, (chunk + 1) * kFramesPerChunk);
    for (int t = chunk * kFramesPerChunk; t < end; ++t) {
      qt = q.row(t).transpose();
      st.cost += evaluateFrame(model, theta, noise, loss, frameReadings(obs, t), qt, eo, &w);
      Eigen::LLT<Eigen::MatrixXd> llt;
      if (leverage) {
        accumulateNormalEquations(w, &H, &g);
        H.diagonal().array() += 1e-12 * std::max(1.0, H.diagonal().maxCoeff());
        llt.compute(H);
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
          const std::vector<int>& cols = *rj.q_cols;
          for (int r = 0; r < rj.rows; ++r) {
            col.setZero();
            for (size_t c = 0; c < cols.size(); ++c) col[cols[c]] = rj.Jq(r, c);
            st.leverage[g_idx] += llt.matrixL().solve(col).squaredNorm();
          }
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
                           const std::string& stage) {
  IterationReport r;
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


// Observations restricted to the given frames.
Observations selectFrames(const Observations& obs, const std::vector<int>& frames) {
  Observations out;
  out.num_frames = static_cast<int>(frames.size());
  out.marker.resize(out.num_frames, obs.marker.cols());
  out.joint.resize(out.num_frames, obs.joint.cols());
  out.tendon.resize(out.num_frames, obs.tendon.cols());
  for (int i = 0; i < out.num_frames; ++i) {
    out.marker.row(i) = obs.marker.row(frames[i]);
    out.joint.row(i) = obs.joint.row(frames[i]);
    out.tendon.row(i) = obs.tendon.row(frames[i]);
  }
  return out;
}

// The joint angle a one-joint sensor implies if the log spans 80% of the
// joint's range: q = alpha (p - mean p) + mid. Such a guess has the right
// time course and roughly the right scale; only alpha's sign is unknown,
// and a greedy sweep picks each sign by how well the markers then fit.
struct PotGuess {
  int sensor = -1;   // joint sensor index
  int column = -1;   // q index
  double alpha = 0, mean = 0, mid = 0;
};

std::vector<PotGuess> makePotGuesses(const RobotModel& robot, const SensorSet& sensors,
                                     const SensorParameters& theta, const Observations& obs) {
  std::vector<PotGuess> out;
  std::vector<bool> covered(robot.dof(), false);
  for (size_t s = 0; s < sensors.joint_sensors.size(); ++s) {
    const JointSensorConfig& sc = sensors.joint_sensors[s];
    const MovableJoint& mj = robot.movableJoints()[sc.joint];
    if (mj.is_mimic || covered[mj.q_index]) continue;
    double lo = robot.lowerLimits()[mj.q_index], hi = robot.upperLimits()[mj.q_index];
    if (!std::isfinite(lo) || !std::isfinite(hi)) lo = -M_PI, hi = M_PI;
    double pmin = INFINITY, pmax = -INFINITY, sum = 0;
    int n = 0;
    for (int t = 0; t < obs.num_frames; ++t) {
      const double p = obs.joint(t, s);
      if (std::isnan(p)) continue;
      pmin = std::min(pmin, p), pmax = std::max(pmax, p), sum += p, ++n;
    }
    if (n < 2) continue;
    PotGuess g;
    g.sensor = static_cast<int>(s);
    g.column = mj.q_index;
    g.mean = sum / n;
    g.mid = 0.5 * (lo + hi);
    if (sc.fixed) {
      // Known calibration: the exact inverse.
      const GainBias& gb = theta.joint_sensor[s];
      if (gb.gain == 0) continue;
      g.alpha = 1.0 / gb.gain;
      g.mid = (g.mean - gb.bias) / gb.gain;
    } else {
      if (!(pmax > pmin)) continue;
      g.alpha = 0.8 * (hi - lo) / (pmax - pmin);
    }
    covered[mj.q_index] = true;
    out.push_back(g);
  }
  return out;
}

void applyPotGuesses(const std::vector<PotGuess>& guesses, const Observations& obs,
                     RowMatrix* q) {
  for (const PotGuess& g : guesses) {
    double last = g.mid;
    for (int t = 0; t < obs.num_frames; ++t) {
      const double p = obs.joint(t, g.sensor);
      if (!std::isnan(p)) last = g.alpha * (p - g.mean) + g.mid;
      (*q)(t, g.column) = last;
    }
  }
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

CalibrationResult calibrate(const RobotModel& robot, const SensorSet& sensors,
                            const SensorParameters& seed, const Observations& obs,
                            const CalibrationOptions& options, RowMatrix* joint_angles,
                            const RowMatrix* q0) {
  std::string error;
  if (!options.isValid(&error)) throw std::invalid_argument(error);
  if (obs.num_frames < 1) throw std::invalid_argument("the log has no frames");
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
  // "Before": each q_t fitted to the seed θ (a few LM steps per frame).
  {
    QState seed_state = state;
    QPhaseOptions qo;
    qo.method = QPhaseMethod::kLmBatch;
    qo.max_steps = 10;
    qo.threads = threads;
    qPhase(model, theta, noise, loss, obs, qo, &ws, &seed_state);
    const PassStats before = costPass(model, theta, noise, seed_noise, loss, obs, seed_state.q,
                                      false, threads, &ws);
    for (int g = 0; g < kNumSensorGroups; ++g)
      summary.before_rms[g] = before.count[g] > 0 ? std::sqrt(before.sse[g] / before.count[g]) : 0;
  }
  PassStats st = costPass(model, theta, noise, seed_noise, loss, obs, state.q, false,
                          threads, &ws);
  summary.initial_cost = st.cost;

  const bool has_markers = !sensors.markers.empty();
  const bool marker_group_free =
      has_markers && (!sensors.mocap_frame_fixed ||
                      std::any_of(sensors.markers.begin(), sensors.markers.end(),
                                  [](const MarkerConfig& m) { return !m.fixed; }));
  std::vector<PotGuess> guesses;
  if (options.wide_basin_init && has_markers)
    guesses = makePotGuesses(robot, sensors, theta, obs);
  if (options.wide_basin_init && has_markers) {
    QPhaseOptions qo;
    qo.method = QPhaseMethod::kLmIter;
    qo.threads = threads;
    qo.eval.group_weight[1] = qo.eval.group_weight[2] = 0.0;
    ThetaPhaseOptions to;
    to.threads = threads;
    to.update[1] = to.update[2] = false;
    if (!guesses.empty()) {
      // Pick each guess's sign on a subsample of frames.
      std::vector<int> sub;
      const int n_sub = std::min(obs.num_frames, 150);
      for (int i = 0; i < n_sub; ++i)
        sub.push_back(static_cast<int>(static_cast<long>(i) * obs.num_frames / n_sub));
      const Observations so = selectFrames(obs, sub);
      QState ss;
      ss.q = neutralPose(robot).transpose().replicate(so.num_frames, 1);
      // A candidate's score: how well the markers fit once the mocap frame
      // and markers are re-solved in closed form and the joints no pot
      // covers (gimbals driven by linear pots, say) follow the markers.
      QPhaseOptions free_only = qo;
      free_only.method = QPhaseMethod::kLmBatch;
      free_only.max_steps = 8;
      free_only.frozen.assign(robot.dof(), false);
      bool any_free = false;
      for (const PotGuess& g : guesses) free_only.frozen[g.column] = true;
      for (int j = 0; j < robot.dof(); ++j) any_free |= !free_only.frozen[j];
      auto markerCost = [&](SensorParameters* th) {
        ss.q = neutralPose(robot).transpose().replicate(so.num_frames, 1);
        applyPotGuesses(guesses, so, &ss.q);
        for (int round = 0; round < (any_free ? 2 : 1); ++round) {
          if (marker_group_free) {
            initialiseMarkerGroup(model, so, ss, 2, threads, &ws, th);
            thetaPhase(model, noise, loss, so, ss, to, &ws, th);
          }
          if (any_free) qPhase(model, *th, noise, loss, so, free_only, &ws, &ss);
        }
        return totalCost(model, *th, noise, loss, so, qo.eval, threads, &ws, &ss);
      };
      SensorParameters th = theta;
      double best = markerCost(&th);
      // The likeliest wrong answers are mirror images of the whole motion:
      // the world turned half a turn about a base axis a flips the sign of
      // every joint whose axis is perpendicular to a. Try those patterns
      // (and all signs flipped) before the greedy single-sign sweeps.
      {
        KinematicsWorkspace kin(robot);
        forwardKinematics(robot, neutralPose(robot), &kin);
        std::vector<std::vector<bool>> patterns(4, std::vector<bool>(guesses.size(), true));
        for (size_t i = 0; i < guesses.size(); ++i) {
          const Eigen::Vector3d u =
              kin.joint_axis[robot.qJoints()[guesses[i].column]].normalized();
          for (int a = 0; a < 3; ++a) patterns[1 + a][i] = std::abs(u[a]) < 0.7;
        }
        auto flip = [&](const std::vector<bool>& pattern) {
          for (size_t i = 0; i < guesses.size(); ++i)
            if (pattern[i] && !sensors.joint_sensors[guesses[i].sensor].fixed)
              guesses[i].alpha = -guesses[i].alpha;
        };
        int best_pattern = -1;
        for (int k = 0; k < static_cast<int>(patterns.size()); ++k) {
          flip(patterns[k]);
          th = theta;
          const double c = markerCost(&th);
          flip(patterns[k]);
          if (c < best) best = c, best_pattern = k;
        }
        if (best_pattern >= 0) flip(patterns[best_pattern]);
      }
      for (int sweep = 0; sweep < 2; ++sweep) {
        bool changed = false;
        for (PotGuess& g : guesses) {
          if (sensors.joint_sensors[g.sensor].fixed) continue;
          g.alpha = -g.alpha;
          SensorParameters trial = theta;
          const double c = markerCost(&trial);
          if (c < best) {
            best = c;
            changed = true;
          } else {
            g.alpha = -g.alpha;
          }
        }
        if (!changed) break;
      }
      applyPotGuesses(guesses, obs, &state.q);
      if (std::getenv("STAC_DEBUG")) {
        for (const PotGuess& g : guesses) std::fprintf(stderr, "guess %d alpha %g\n", g.sensor, g.alpha);
        std::fprintf(stderr, "best %g\n", best);
      }
      for (const PotGuess& g : guesses) {
        if (sensors.joint_sensors[g.sensor].fixed) continue;
        GainBias& gb = theta.joint_sensor[g.sensor];
        gb.gain = 1.0 / g.alpha;
        gb.bias = g.mean - g.mid / g.alpha;
      }
      qo.eval.group_weight[1] = 1.0;  // pots now carry their guessed map
      to.update[1] = true;
    }
    if (marker_group_free)
      initialiseMarkerGroup(model, obs, state, 3, threads, &ws, &theta);
    double prev = -1, init_lambda = 1e-3;
    const bool all_covered = static_cast<int>(guesses.size()) == robot.dof();
    for (int it = 0; it < 30; ++it) {
      double c = 0;
      if (it < 2 && guesses.empty()) {
        // No pot to guess from: track through time from the neutral pose
        // (twice: the second time with the mocap frame and markers the
        // first pass allowed).
        QPhaseOptions tr = qo;
        tr.method = QPhaseMethod::kLmBatch;
        tr.max_steps = 20;
        c = trackingPass(model, theta, noise, loss, obs, tr, neutralPose(robot), 32, &ws, &state);
      } else {
        c = qPhase(model, theta, noise, loss, obs, qo, &ws, &state);
      }
      if (marker_group_free || !guesses.empty())
        thetaPhase(model, noise, loss, obs, state, to, &ws, &theta);
      // Coupled steps once the alternation stalls (they cost more).
      if (options.coupled_steps && prev > 0 && prev - c < 1e-2 * prev)
        c = coupledStep(model, noise, loss, obs, threads, &ws, &init_lambda, &theta, &state,
                        qo.eval);
      if (prev > 0 && std::abs(prev - c) <= 1e-4 * prev) break;
      prev = c;
    }
    (void)all_covered;
    ThetaPhaseOptions pots;
    pots.threads = threads;
    pots.update[0] = false;
    thetaPhase(model, noise, loss, obs, state, pots, &ws, &theta);
    st = costPass(model, theta, noise, seed_noise, loss, obs, state.q, options.adapt_variance,
                  threads, &ws);
    if (options.adapt_variance) {
      adaptNoise(st, seed_noise, kappa, &noise);
      st = costPass(model, theta, noise, seed_noise, loss, obs, state.q, false, threads, &ws);
    }
    if (options.progress) options.progress(makeReport(0, st, start, "init"));
  } else if (options.progress) {
    options.progress(makeReport(0, st, start, "seed"));
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
      if (options.progress) options.progress(makeReport(round + 1, st, start, "joint"));
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
    for (int it = 1; it <= options.max_iterations; ++it) {
      qPhase(model, theta, noise, loss, obs, qo, &ws, &state);
      thetaPhase(model, noise, loss, obs, state, to, &ws, &theta);
      // Where q and θ are strongly coupled the alternation slows to a crawl;
      // a coupled Gauss-Newton step (q_t eliminated per frame, schur.hpp)
      // then finishes the job at the same cost per frame.
      if (options.coupled_steps) {
        EvalOptions eo;
        const double c_alt = totalCost(model, theta, noise, loss, obs, eo, threads, &ws, &state);
        if (cost - c_alt < 1e-2 * cost)
          coupledStep(model, noise, loss, obs, threads, &ws, &lambda, &theta, &state);
      }
      st = costPass(model, theta, noise, seed_noise, loss, obs, state.q,
                    options.adapt_variance, threads, &ws);
      const double rel = (cost - st.cost) / std::max(cost, 1e-300);
      iterations = it;
      double change = 0;
      if (options.progress) options.progress(makeReport(it, st, start, "stac"));
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
  auto rms_sigma = [](const std::vector<double>& v) {
    double s = 0;
    for (double x : v) s += x * x;
    return v.empty() ? 0.0 : std::sqrt(s / v.size());
  };
  summary.group_present[0] = !sensors.markers.empty();
  summary.group_present[1] = !sensors.joint_sensors.empty();
  summary.group_present[2] = !sensors.tendon_sensors.empty();
  summary.group_sigma[0] = rms_sigma(noise.marker);
  summary.group_sigma[1] = rms_sigma(noise.joint);
  summary.group_sigma[2] = rms_sigma(noise.tendon);
  summary.wall_time = std::chrono::duration<double>(Clock::now() - start).count();
  if (joint_angles) *joint_angles = state.q;
  return result;
}

}  // namespace stac
