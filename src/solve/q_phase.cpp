#include "solve/q_phase.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>

#include "solve/lm_damping.hpp"
#include "solve/parallel.hpp"
#include "solve/whole_turns.hpp"

namespace stac {

void accumulateNormalEquations(const FrameWorkspace& ws, Eigen::MatrixXd* H,
                               Eigen::VectorXd* g) {
  H->setZero();
  g->setZero();
  for (int i = 0; i < ws.count; ++i) {
    const ReadingJacobian& rj = ws.readings[i];
    const std::vector<int>& cols = *rj.q_cols;
    const int n = static_cast<int>(cols.size());
    const auto J = rj.Jq.topLeftCorner(rj.rows, n);
    const auto r = rj.r.head(rj.rows);
    for (int a = 0; a < n; ++a) {
      (*g)[cols[a]] += J.col(a).dot(r);
      for (int b = 0; b <= a; ++b) (*H)(cols[a], cols[b]) += J.col(a).dot(J.col(b));
    }
  }
  H->triangularView<Eigen::StrictlyUpper>() = H->transpose();
}

namespace {

// What the virtual points of tracked bodies add to the markers' leverage
// (addGroupLeverage): each body's leverage, tr(J H⁻¹ Jᵀ) over its points'
// rows, (rowsPerDim - 1) times.
template <typename Hinv>
double bodyLeverageExcess(const FrameWorkspace& w, const MarkerBodies& bodies, const Hinv& hinv) {
  if (bodies.empty()) return 0.0;
  std::vector<double> lev(bodies.rank.size(), 0.0);
  std::vector<int> present(bodies.rank.size(), 0);
  for (int i = 0; i < w.count; ++i) {
    const ReadingJacobian& rj = w.readings[i];
    if (rj.group != SensorGroup::kMarker) continue;
    const int b = bodies.body_of_marker[rj.sensor];
    if (b < 0) continue;
    const std::vector<int>& cols = *rj.q_cols;
    for (int r = 0; r < rj.rows; ++r)
      for (size_t a = 0; a < cols.size(); ++a)
        for (size_t c = 0; c < cols.size(); ++c)
          lev[b] += rj.Jq(r, a) * hinv(cols[a], cols[c]) * rj.Jq(r, c);
    ++present[b];
  }
  double excess = 0;
  for (size_t b = 0; b < lev.size(); ++b)
    excess += (bodies.rowsPerDim(static_cast<int>(b), present[b]) - 1) * lev[b];
  return excess;
}

}  // namespace

// Cholesky and L⁻¹ in plain loops: they beat Eigen's blocked kernels at
// these sizes. The markers' share is what the pots' and tendons' (one row,
// few columns each: entries of H⁻¹ = L⁻ᵀ L⁻¹) leave of tr(H⁻¹ H), so no
// marker's 3 x k block is touched.
void addGroupLeverage(const FrameWorkspace& w, const MarkerBodies& bodies, Eigen::MatrixXd* H,
                      Eigen::MatrixXd* Linv, double leverage[kNumSensorGroups]) {
  const int n = static_cast<int>(H->rows());
  const double eps = 1e-12 * std::max(1.0, H->diagonal().maxCoeff());
  H->diagonal().array() += eps;
  // In-place Cholesky, then L⁻¹ (both lower).
  Eigen::MatrixXd& L = *H;
  for (int j = 0; j < n; ++j) {
    double d = L(j, j);
    for (int k = 0; k < j; ++k) d -= L(j, k) * L(j, k);
    if (!(d > 0)) return;  // not positive definite: leave this frame out
    d = std::sqrt(d);
    L(j, j) = d;
    for (int i = j + 1; i < n; ++i) {
      double s = L(i, j);
      for (int k = 0; k < j; ++k) s -= L(i, k) * L(j, k);
      L(i, j) = s / d;
    }
  }
  Eigen::MatrixXd& M = *Linv;
  for (int j = 0; j < n; ++j) {
    M(j, j) = 1.0 / L(j, j);
    for (int i = j + 1; i < n; ++i) {
      double s = 0;
      for (int k = j; k < i; ++k) s -= L(i, k) * M(k, j);
      M(i, j) = s / L(i, i);
    }
  }
  // (H⁻¹)_ab = Σ_k≥max(a,b) L⁻¹(k,a) L⁻¹(k,b).
  auto hinv = [&](int a, int b) {
    const int lo = std::max(a, b);
    return M.col(a).segment(lo, n - lo).dot(M.col(b).segment(lo, n - lo));
  };
  double others = 0, trace = 0;
  for (int i = 0; i < n; ++i) trace += hinv(i, i);
  for (int i = 0; i < w.count; ++i) {
    const ReadingJacobian& rj = w.readings[i];
    if (rj.group == SensorGroup::kMarker) continue;
    const std::vector<int>& cols = *rj.q_cols;
    double lev = 0;
    for (size_t a = 0; a < cols.size(); ++a)
      for (size_t b = 0; b < cols.size(); ++b)
        lev += rj.Jq(0, a) * hinv(cols[a], cols[b]) * rj.Jq(0, b);
    leverage[static_cast<int>(rj.group)] += lev;
    others += lev;
  }
  // tr(H⁻¹ (H - εI)) = n - ε tr(H⁻¹): a joint no reading sees adds 0.
  leverage[static_cast<int>(SensorGroup::kMarker)] +=
      n - eps * trace - others + bodyLeverageExcess(w, bodies, hinv);
}

void widenedLimits(const RobotModel& robot, Eigen::VectorXd* lower, Eigen::VectorXd* upper) {
  *lower = robot.lowerLimits();
  *upper = robot.upperLimits();
  for (int i = 0; i < robot.dof(); ++i) {
    const double margin = 0.05 * ((*upper)[i] - (*lower)[i]);
    if (std::isfinite(margin)) (*lower)[i] -= margin, (*upper)[i] += margin;
  }
}

namespace {
// Whether each joint of each row of q lies within `margin` of its bounds
// or beyond them (margin < 0: beyond them by more than -margin); a joint
// whose bounds coincide, only beyond them by more than |margin|.
Eigen::Matrix<bool, Eigen::Dynamic, Eigen::Dynamic> outside(const RowMatrix& q,
                                                            const Eigen::VectorXd& lower,
                                                            const Eigen::VectorXd& upper,
                                                            double margin) {
  Eigen::Matrix<bool, Eigen::Dynamic, Eigen::Dynamic> out(q.rows(), q.cols());
  for (int j = 0; j < q.cols(); ++j) {
    const double m = upper[j] > lower[j] ? margin : -std::abs(margin);
    for (int t = 0; t < q.rows(); ++t)
      out(t, j) = q(t, j) <= lower[j] + m || q(t, j) >= upper[j] - m;
  }
  return out;
}
}  // namespace

Eigen::Matrix<bool, Eigen::Dynamic, Eigen::Dynamic> atWidenedLimit(const RobotModel& robot,
                                                                   const RowMatrix& q) {
  Eigen::VectorXd lower, upper;
  widenedLimits(robot, &lower, &upper);
  return outside(q, lower, upper, 1e-6);
}

Eigen::Matrix<bool, Eigen::Dynamic, Eigen::Dynamic> beyondLimits(const RobotModel& robot,
                                                                 const RowMatrix& q) {
  return outside(q, robot.lowerLimits(), robot.upperLimits(), -1e-6);
}

namespace {

struct FrameSolver {
  const MeasurementModel& model;
  const SensorParameters& theta;
  const NoiseModel& noise;
  const RobustLoss& loss;
  const QPhaseOptions& options;
  FrameOptions with_jac, no_jac;
  Eigen::VectorXd lower, upper;
  Eigen::MatrixXd H, A;
  Eigen::VectorXd g, step, q_new;
  std::vector<int> free_cols;  // with options.frozen: the columns not frozen
  Eigen::MatrixXd A_free;      // their damped system (factored in place), solution
  Eigen::VectorXd step_free;
  std::vector<TurnSensor> turn_sensors;  // whole_turns.hpp
  Eigen::VectorXd q_turned;

  FrameSolver(const MeasurementModel& m, const SensorParameters& th,
              const NoiseModel& n, const RobustLoss& l, const QPhaseOptions& o)
      : model(m), theta(th), noise(n), loss(l), options(o),
        with_jac(o.eval), no_jac(o.eval),
        H(m.dof(), m.dof()), A(m.dof(), m.dof()), g(m.dof()),
        step(m.dof()), q_new(m.dof()) {
    with_jac.jacobians = true;
    with_jac.theta_jacobians = false;
    no_jac.jacobians = false;
    no_jac.theta_jacobians = false;
    widenedLimits(m.robot(), &lower, &upper);
    if (!o.frozen.empty())
      for (int i = 0; i < m.dof(); ++i)
        if (!o.frozen[i]) free_cols.push_back(i);
    const int k = static_cast<int>(free_cols.size());
    A_free.resize(k, k);
    step_free.resize(k);
    if (o.whole_turns) turn_sensors = turnSensors(m, lower, upper, o.frozen);
  }

  void project(Eigen::VectorXd* q) const { *q = q->cwiseMax(lower).cwiseMin(upper); }

  double eval(const FrameReadings& fr, const Eigen::VectorXd& q, bool jac,
              FrameWorkspace* ws) {
    return evaluateFrame(model, theta, noise, loss, fr, q, jac ? with_jac : no_jac, ws);
  }

  // Solves (H + λ D + ε I) step = -g; D = diag(H) keeps LM scale-invariant,
  // ε keeps joints that no reading sees at their current value.
  void solveDamped(double lambda) {
    if (!options.frozen.empty()) {
      const double eps = ridge(H.diagonal());
      // Frozen columns: the system of the free ones only (often a few).
      const int k = static_cast<int>(free_cols.size());
      for (int a = 0; a < k; ++a) {
        for (int b = 0; b < k; ++b) A_free(a, b) = H(free_cols[a], free_cols[b]);
        A_free(a, a) += lambda * H(free_cols[a], free_cols[a]) + eps;
        step_free[a] = -g[free_cols[a]];
      }
      Eigen::LLT<Eigen::Ref<Eigen::MatrixXd>> llt(A_free);  // in place: no allocation
      llt.solveInPlace(step_free);
      step.setZero();
      if (llt.info() != Eigen::Success || !step_free.allFinite()) return;
      for (int a = 0; a < k; ++a) step[free_cols[a]] = step_free[a];
      return;
    }
    A = H;
    addDamping(lambda, H, &A);
    Eigen::LLT<Eigen::MatrixXd> llt(A);
    step = llt.solve(-g);
    if (llt.info() != Eigen::Success || !step.allFinite()) step.setZero();
  }

  // The q-phase's step of one frame, as options.method says.
  double solve(const FrameReadings& fr, Eigen::Ref<Eigen::RowVectorXd> q_row, double* lambda,
               FrameWorkspace* ws) {
    switch (options.method) {
      case QPhaseMethod::kLmIter: return lm(fr, q_row, lambda, 1, ws);
      case QPhaseMethod::kLmBatch: return lm(fr, q_row, lambda, options.max_steps, ws);
      case QPhaseMethod::kBfgs: return bfgs(fr, q_row, options.max_steps, ws);
    }
    return lm(fr, q_row, lambda, 1, ws);
  }

  // Moves q by the whole turns a joint sensor's reading asks for where that
  // lowers the frame's cost (whole_turns.hpp). Returns the cost.
  double turn(const FrameReadings& fr, Eigen::Ref<Eigen::RowVectorXd> q_row, double cost,
              FrameWorkspace* ws) {
    if (fr.joint == nullptr) return cost;
    for (const TurnSensor& ts : turn_sensors) {
      const int k = turnsToFit(ts, theta.joint_sensor[ts.sensor], noise.joint[ts.sensor],
                               fr.joint[ts.sensor], q_row[ts.column]);
      if (k == 0) continue;
      q_turned = q_row.transpose();
      q_turned[ts.column] += 2 * M_PI * k;
      if (q_turned[ts.column] < lower[ts.column] || q_turned[ts.column] > upper[ts.column])
        continue;
      // Better beyond rounding: a turn leaves the kinematics the same but
      // for the last bits of sin and cos.
      const double c = eval(fr, q_turned, false, ws);
      if (c < cost * (1 - 1e-9)) {
        q_row = q_turned.transpose();
        cost = c;
      }
    }
    return cost;
  }

  // Levenberg-Marquardt; returns the final cost.
  double lm(const FrameReadings& fr, Eigen::Ref<Eigen::RowVectorXd> q_row,
            double* lambda, int max_accepted, FrameWorkspace* ws) {
    Eigen::VectorXd q = q_row.transpose();
    double cost = eval(fr, q, true, ws);
    int accepted = 0;
    for (int tries = 0; accepted < max_accepted && tries < 4 * max_accepted + 6; ++tries) {
      accumulateNormalEquations(*ws, &H, &g);
      if (g.norm() < 1e-14) break;
      bool improved = false;
      for (int attempt = 0; attempt < 8; ++attempt) {
        solveDamped(*lambda);
        q_new = q + step;
        project(&q_new);
        const double c = eval(fr, q_new, false, ws);
        if (c < cost) {
          const double rel = (cost - c) / std::max(cost, 1e-300);
          q = q_new;
          cost = c;
          *lambda = acceptedStep(kFrameSchedule, *lambda);
          improved = true;
          ++accepted;
          if (max_accepted > 1 &&
              (rel < options.step_tolerance || step.norm() < options.step_tolerance))
            accepted = max_accepted;
          break;
        }
        *lambda = rejectedStep(kFrameSchedule, *lambda);
      }
      if (!improved) break;
      if (accepted < max_accepted) cost = eval(fr, q, true, ws);
    }
    q_row = q.transpose();
    return cost;
  }

  // BFGS on the frame's cost with a Gauss-Newton inverse-Hessian start and
  // Armijo backtracking.
  double bfgs(const FrameReadings& fr, Eigen::Ref<Eigen::RowVectorXd> q_row,
              int max_steps, FrameWorkspace* ws) {
    const int n = model.dof();
    Eigen::VectorXd q = q_row.transpose();
    double cost = eval(fr, q, true, ws);
    accumulateNormalEquations(*ws, &H, &g);
    A = H;
    const double eps = 1e-9 * std::max(1.0, H.diagonal().maxCoeff());
    for (int i = 0; i < n; ++i) A(i, i) += 1e-3 * H(i, i) + eps;
    Eigen::MatrixXd Hinv = A.llt().solve(Eigen::MatrixXd::Identity(n, n));
    if (!Hinv.allFinite()) Hinv = Eigen::MatrixXd::Identity(n, n);
    Eigen::VectorXd grad = g, q_try(n), grad_new(n), s(n), y(n);
    for (int it = 0; it < max_steps; ++it) {
      Eigen::VectorXd dir = -Hinv * grad;
      double slope = grad.dot(dir);
      if (slope >= 0) {
        dir = -grad;
        slope = -grad.squaredNorm();
        Hinv.setIdentity();
      }
      double alpha = 1.0, c = cost;
      bool ok = false;
      for (int ls = 0; ls < 20; ++ls, alpha *= 0.5) {
        q_try = q + alpha * dir;
        project(&q_try);
        c = eval(fr, q_try, false, ws);
        if (c <= cost + 1e-4 * alpha * slope) {
          ok = true;
          break;
        }
      }
      if (!ok) break;
      const double rel = (cost - c) / std::max(cost, 1e-300);
      eval(fr, q_try, true, ws);
      accumulateNormalEquations(*ws, &H, &grad_new);
      s = q_try - q;
      y = grad_new - grad;
      q = q_try;
      cost = c;
      grad = grad_new;
      const double sy = s.dot(y);
      if (sy > 1e-300) {
        const Eigen::VectorXd Hy = Hinv * y;
        const double yHy = y.dot(Hy);
        Hinv += ((sy + yHy) / (sy * sy)) * (s * s.transpose()) -
                (Hy * s.transpose() + s * Hy.transpose()) / sy;
      }
      if (rel < options.step_tolerance || s.norm() < options.step_tolerance) break;
    }
    q_row = q.transpose();
    return cost;
  }
};

}  // namespace

double qPhase(const MeasurementModel& model, const SensorParameters& theta,
              const NoiseModel& noise, const RobustLoss& loss,
              const Observations& obs, const QPhaseOptions& options,
              std::vector<FrameWorkspace>* workspaces, QState* state) {
  const int T = obs.num_frames;
  const int threads = std::min<int>(resolveThreads(options.threads),
                                    static_cast<int>(workspaces->size()));
  if (state->lambda.size() != T) state->lambda = Eigen::VectorXd::Constant(T, 1e-3);
  state->cost.resize(T);
  std::vector<FrameSolver> solvers;
  for (int i = 0; i < threads; ++i) solvers.emplace_back(model, theta, noise, loss, options);
  parallelFor(numChunks(T), threads, [&](int chunk, int tid) {
    FrameSolver& solver = solvers[tid];
    FrameWorkspace& ws = (*workspaces)[tid];
    const int end = std::min(T, (chunk + 1) * kFramesPerChunk);
    for (int t = chunk * kFramesPerChunk; t < end; ++t) {
      const FrameReadings fr = frameReadings(obs, t);
      auto q_row = state->q.row(t);
      state->cost[t] = solver.solve(fr, q_row, &state->lambda[t], &ws);
      // A frame turned is solved again from there: it left its basin.
      const double before = state->cost[t];
      state->cost[t] = solver.turn(fr, q_row, before, &ws);
      if (state->cost[t] < before) state->cost[t] = solver.solve(fr, q_row, &state->lambda[t], &ws);
    }
  });
  return state->cost.sum();
}

double trackingPass(const MeasurementModel& model, const SensorParameters& theta,
                    const NoiseModel& noise, const RobustLoss& loss,
                    const Observations& obs, const QPhaseOptions& options,
                    const Eigen::VectorXd& start, int segments,
                    std::vector<FrameWorkspace>* workspaces, QState* state) {
  const int T = obs.num_frames;
  const int threads = std::min<int>(resolveThreads(options.threads),
                                    static_cast<int>(workspaces->size()));
  state->lambda = Eigen::VectorXd::Constant(T, 1e-3);
  state->cost.resize(T);
  segments = std::max(1, std::min(segments, T));
  std::vector<FrameSolver> solvers;
  for (int i = 0; i < threads; ++i) solvers.emplace_back(model, theta, noise, loss, options);
  parallelFor(segments, threads, [&](int seg, int tid) {
    const int begin = static_cast<int>(static_cast<long>(T) * seg / segments);
    const int end = static_cast<int>(static_cast<long>(T) * (seg + 1) / segments);
    for (int t = begin; t < end; ++t) {
      if (t == begin) state->q.row(t) = start.transpose();
      else state->q.row(t) = state->q.row(t - 1);
      state->cost[t] = solvers[tid].lm(frameReadings(obs, t), state->q.row(t),
                                       &state->lambda[t], options.max_steps,
                                       &(*workspaces)[tid]);
    }
  });
  return state->cost.sum();
}

double totalCost(const MeasurementModel& model, const SensorParameters& theta,
                 const NoiseModel& noise, const RobustLoss& loss,
                 const Observations& obs, const FrameOptions& eval, int threads,
                 std::vector<FrameWorkspace>* workspaces, QState* state) {
  const int T = obs.num_frames;
  threads = std::min<int>(resolveThreads(threads), static_cast<int>(workspaces->size()));
  FrameOptions e = eval;
  e.jacobians = false;
  e.theta_jacobians = false;
  state->cost.resize(T);
  parallelFor(numChunks(T), threads, [&](int chunk, int tid) {
    const int end = std::min(T, (chunk + 1) * kFramesPerChunk);
    for (int t = chunk * kFramesPerChunk; t < end; ++t) {
      Eigen::VectorXd q = state->q.row(t).transpose();
      state->cost[t] = evaluateFrame(model, theta, noise, loss, frameReadings(obs, t), q,
                                     e, &(*workspaces)[tid]);
    }
  });
  return state->cost.sum();
}

}  // namespace stac
