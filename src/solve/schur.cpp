#include "solve/schur.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>

#include "solve/lm_damping.hpp"
#include "solve/origin_prior.hpp"
#include "solve/parallel.hpp"
#include "solve/pot_chart.hpp"

namespace stac {

void accumulateThetaNormalEquations(const ReadingJacobian& rj, const std::vector<int>& free_of,
                                    Eigen::MatrixXd* S, Eigen::VectorXd* g) {
  for (int b = 0; b < rj.theta_count; ++b) {
    const int fb = free_of[rj.theta_index[b]];
    if (fb < 0) continue;
    const auto jb = rj.Jtheta.col(b).head(rj.rows);
    if (g) (*g)[fb] += jb.dot(rj.r.head(rj.rows));
    for (int c = 0; c <= b; ++c) {
      const int fc = free_of[rj.theta_index[c]];
      if (fc >= 0) (*S)(std::max(fb, fc), std::min(fb, fc)) += rj.Jtheta.col(c).head(rj.rows).dot(jb);
    }
  }
}

namespace {
constexpr int kBlocks = kReductionBlocks;
constexpr int kBatch = 8;  // frames per rank update

struct FrameSystem {
  Eigen::MatrixXd Hqq, Hqt;
  Eigen::VectorXd gq;
};

// Evaluates frame t and forms its q-blocks; accumulates the θθ block and
// gradient into S/gt (lower triangle) when given.
void frameSystem(const MeasurementModel& model, const SensorParameters& theta,
                 const NoiseModel& noise, const RobustLoss& loss, const Observations& obs,
                 const Eigen::VectorXd& qt, int t, const std::vector<int>& free_of,
                 FrameWorkspace* w, FrameSystem* fs, Eigen::MatrixXd* S, Eigen::VectorXd* gt,
                 Eigen::VectorXd* D, double* cost, const FrameOptions& groups) {
  FrameOptions eo = groups;
  eo.jacobians = true;
  eo.theta_jacobians = true;
  *cost += evaluateFrame(model, theta, noise, loss, frameReadings(obs, t), qt, eo, w);
  accumulateNormalEquations(*w, &fs->Hqq, &fs->gq);
  fs->Hqt.setZero();
  for (int i = 0; i < w->count; ++i) {
    const ReadingJacobian& rj = w->readings[i];
    const std::vector<int>& cols = *rj.q_cols;
    for (int b = 0; b < rj.theta_count; ++b) {
      const int fb = free_of[rj.theta_index[b]];
      if (fb < 0) continue;
      const auto jb = rj.Jtheta.col(b).head(rj.rows);
      for (size_t a = 0; a < cols.size(); ++a) fs->Hqt(cols[a], fb) += rj.Jq.col(a).head(rj.rows).dot(jb);
    }
    if (S) accumulateThetaNormalEquations(rj, free_of, S, gt);
    if (!D) continue;
    for (int b = 0; b < rj.theta_count; ++b) {
      const int fb = free_of[rj.theta_index[b]];
      if (fb >= 0) (*D)[fb] += rj.Jtheta.col(b).head(rj.rows).squaredNorm();
    }
  }
}

void dampQ(double lambda, Eigen::MatrixXd* H) { addDamping(lambda, *H, H); }

// What reduceOntoTheta accumulates per block of frames (D and B only when
// asked for), summed in block order so that the result does not depend on
// the number of threads.
struct BlockSums {
  BlockSums(int nf, bool diag, bool outer)
      : S(kBlocks, Eigen::MatrixXd::Zero(nf, nf)),
        B(outer ? kBlocks : 0, Eigen::MatrixXd::Zero(nf, nf)),
        g(kBlocks, Eigen::VectorXd::Zero(nf)),
        D(diag ? kBlocks : 0, Eigen::VectorXd::Zero(nf)),
        cost(kBlocks, 0.0),
        q_decrement(kBlocks, 0.0) {}
  std::vector<Eigen::MatrixXd> S, B;
  std::vector<Eigen::VectorXd> g, D;
  std::vector<double> cost, q_decrement;

  // Into out (S made symmetric from its lower half), *unreduced_diag and
  // *score_outer where given.
  void sum(int nf, ReducedSystem* out, Eigen::VectorXd* unreduced_diag,
           Eigen::MatrixXd* score_outer) const {
    out->S = Eigen::MatrixXd::Zero(nf, nf);
    out->g = Eigen::VectorXd::Zero(nf);
    for (int b = 0; b < kBlocks; ++b) {
      out->S += S[b];
      out->g += g[b];
      out->cost += cost[b];
      out->q_decrement += q_decrement[b];
    }
    // S accumulated H_θθ (lower) minus the eliminated part. LM on the
    // reduced system damps S's own diagonal (a standard choice).
    out->S = out->S.selfadjointView<Eigen::Lower>();
    if (unreduced_diag) {
      unreduced_diag->setZero(nf);
      for (const Eigen::VectorXd& b : D) *unreduced_diag += b;
    }
    if (score_outer) {
      score_outer->setZero(nf, nf);
      for (const Eigen::MatrixXd& b : B) *score_outer += b;
      *score_outer = score_outer->selfadjointView<Eigen::Lower>();
    }
  }
};
}  // namespace

ReducedSystem reduceOntoTheta(const MeasurementModel& model, const SensorParameters& theta,
                              const NoiseModel& noise, const RobustLoss& loss,
                              const Observations& obs, const RowMatrix& q, double lambda,
                              bool with_gradient, int threads,
                              std::vector<FrameWorkspace>* ws, const FrameOptions& groups,
                              const FrameVisitor& visit, Eigen::MatrixXd* score_outer,
                              Eigen::VectorXd* unreduced_diag) {
  ReducedSystem out;
  const ThetaSpace& space = model.thetaSpace();
  out.free_index = space.freeIndex();
  const int nf = space.freeSize();
  const int dof = model.dof();
  const int T = obs.num_frames;
  const std::vector<int>& free_of = space.freePosition();
  BlockSums sums(nf, unreduced_diag != nullptr, score_outer != nullptr);
  const bool need_y = with_gradient || score_outer;
  threads = std::min<int>(resolveThreads(threads), static_cast<int>(ws->size()));
  parallelFor(kBlocks, threads, [&](int block, int tid) {
    FrameSystem fs{Eigen::MatrixXd(dof, dof), Eigen::MatrixXd(dof, nf), Eigen::VectorXd(dof)};
    Eigen::MatrixXd X(dof * kBatch, nf), Y(dof * kBatch, 1), G(nf, kBatch);
    Eigen::VectorXd qt(dof), g_frame(nf);
    Eigen::MatrixXd& S = sums.S[block];
    const int begin = static_cast<int>(static_cast<long>(T) * block / kBlocks);
    const int end = static_cast<int>(static_cast<long>(T) * (block + 1) / kBlocks);
    int in_batch = 0;
    auto flush = [&]() {
      if (in_batch == 0) return;
      const int rows = in_batch * dof;
      S.selfadjointView<Eigen::Lower>().rankUpdate(X.topRows(rows).transpose(), -1.0);
      if (with_gradient) sums.g[block].noalias() -= X.topRows(rows).transpose() * Y.topRows(rows);
      if (score_outer)
        sums.B[block].selfadjointView<Eigen::Lower>().rankUpdate(G.leftCols(in_batch));
      in_batch = 0;
    };
    for (int t = begin; t < end; ++t) {
      qt = q.row(t).transpose();
      // The frame's own θ score first when its outer product is wanted.
      if (score_outer) g_frame.setZero();
      Eigen::VectorXd* g_theta = score_outer ? &g_frame : with_gradient ? &sums.g[block] : nullptr;
      frameSystem(model, theta, noise, loss, obs, qt, t, free_of, &(*ws)[tid], &fs, &S, g_theta,
                  unreduced_diag ? &sums.D[block] : nullptr, &sums.cost[block], groups);
      if (visit) visit(block, (*ws)[tid], fs.Hqq);
      dampQ(lambda, &fs.Hqq);
      Eigen::LLT<Eigen::MatrixXd> llt(fs.Hqq);
      auto Xt = X.middleRows(in_batch * dof, dof);
      auto Yt = Y.middleRows(in_batch * dof, dof);
      Xt = llt.matrixL().solve(fs.Hqt);
      if (need_y) Yt = llt.matrixL().solve(fs.gq);
      if (with_gradient) sums.q_decrement[block] += 0.5 * Yt.squaredNorm();
      if (score_outer) {
        G.col(in_batch) = g_frame - Xt.transpose() * Yt;  // g_θ - H_θq H_qq⁻¹ g_q
        if (with_gradient) sums.g[block] += g_frame;
      }
      if (++in_batch == kBatch) flush();
    }
    flush();
  });
  sums.sum(nf, &out, unreduced_diag, score_outer);
  return out;
}

namespace {

// g_θ - Σ_t H_θq (H_qq + λD)⁻¹ g_q over the free θ, summed in fixed blocks
// of frames; H_θq y is Σ J_θᵀ (J_q y) over the readings, so no H_qθ is
// formed. *cost receives ½ Σ ρ.
Eigen::VectorXd reducedGradient(const MeasurementModel& model, const SensorParameters& theta,
                                const NoiseModel& noise, const RobustLoss& loss,
                                const Observations& obs, const RowMatrix& q, double lambda,
                                const std::vector<int>& free_of, int nf, int threads,
                                std::vector<FrameWorkspace>* ws, const FrameOptions& groups,
                                const FrameVisitor& visit, double* cost) {
  const int dof = model.dof();
  const int T = obs.num_frames;
  std::vector<Eigen::VectorXd> bg(kBlocks, Eigen::VectorXd::Zero(nf));
  std::vector<double> bcost(kBlocks, 0.0);
  FrameOptions eo = groups;
  eo.jacobians = true;
  eo.theta_jacobians = true;
  parallelFor(kBlocks, threads, [&](int block, int tid) {
    FrameWorkspace& w = (*ws)[tid];
    Eigen::MatrixXd H(dof, dof);
    Eigen::VectorXd gq(dof), y(dof), qt(dof);
    const int begin = static_cast<int>(static_cast<long>(T) * block / kBlocks);
    const int end = static_cast<int>(static_cast<long>(T) * (block + 1) / kBlocks);
    for (int t = begin; t < end; ++t) {
      qt = q.row(t).transpose();
      bcost[block] += evaluateFrame(model, theta, noise, loss, frameReadings(obs, t), qt, eo, &w);
      accumulateNormalEquations(w, &H, &gq);
      if (visit) visit(block, w, H);
      dampQ(lambda, &H);
      y = H.llt().solve(gq);
      for (int i = 0; i < w.count; ++i) {
        const ReadingJacobian& rj = w.readings[i];
        const std::vector<int>& cols = *rj.q_cols;
        for (int r = 0; r < rj.rows; ++r) {
          double v = rj.r[r];  // (r - J_q y) row by row
          for (size_t a = 0; a < cols.size(); ++a) v -= rj.Jq(r, a) * y[cols[a]];
          for (int b = 0; b < rj.theta_count; ++b) {
            const int fb = free_of[rj.theta_index[b]];
            if (fb >= 0) bg[block][fb] += rj.Jtheta(r, b) * v;
          }
        }
      }
    }
  });
  Eigen::VectorXd g = Eigen::VectorXd::Zero(nf);
  *cost = 0;
  for (int b = 0; b < kBlocks; ++b) g += bg[b], *cost += bcost[b];
  return g;
}

// Every frame's Δq_t = -(H_qq + λD)⁻¹ (g_q + H_qθ Δθ) for a step Δθ (dfull,
// over all θ entries), with H_qθ Δθ = Σ J_qᵀ (J_θ Δθ) over the readings;
// returns q + Δq, projected onto [lower, upper] when lower is given.
RowMatrix backSubstitute(const MeasurementModel& model, const SensorParameters& theta,
                         const NoiseModel& noise, const RobustLoss& loss, const Observations& obs,
                         const RowMatrix& q, const Eigen::VectorXd& dfull, bool theta_moves,
                         double lambda, const FrameOptions& groups, const Eigen::VectorXd* lower,
                         const Eigen::VectorXd* upper, int threads, std::vector<FrameWorkspace>* ws) {
  const int dof = model.dof();
  const int T = obs.num_frames;
  RowMatrix q_new = q;
  FrameOptions eo = groups;
  eo.jacobians = true;
  eo.theta_jacobians = theta_moves;
  parallelFor(numChunks(T), threads, [&](int chunk, int tid) {
    FrameWorkspace& w = (*ws)[tid];
    Eigen::MatrixXd H(dof, dof);
    Eigen::VectorXd rhs(dof), qt(dof), dq(dof);
    const int end = std::min(T, (chunk + 1) * kFramesPerChunk);
    for (int t = chunk * kFramesPerChunk; t < end; ++t) {
      qt = q.row(t).transpose();
      evaluateFrame(model, theta, noise, loss, frameReadings(obs, t), qt, eo, &w);
      accumulateNormalEquations(w, &H, &rhs);
      for (int i = 0; i < w.count; ++i) {
        const ReadingJacobian& rj = w.readings[i];
        const std::vector<int>& cols = *rj.q_cols;
        for (int r = 0; r < rj.rows; ++r) {
          double v = 0;  // (J_θ Δθ) row by row
          for (int b = 0; b < rj.theta_count; ++b) v += rj.Jtheta(r, b) * dfull[rj.theta_index[b]];
          for (size_t a = 0; a < cols.size(); ++a) rhs[cols[a]] += rj.Jq(r, a) * v;
        }
      }
      dampQ(lambda, &H);
      dq = H.llt().solve(-rhs);
      if (dq.allFinite())
        q_new.row(t) = lower ? (qt + dq).cwiseMax(*lower).cwiseMin(*upper).transpose().eval()
                             : (qt + dq).transpose().eval();
    }
  });
  return q_new;
}

// Frames whose reduced curvature stands for all of them in a coupled step.
constexpr int kCurvatureFrames = 500;

// The back-substitution moves every q_t along its tangent, which is only as
// good as each frame's linearisation. Where some frames are far from linear
// (angles dragged by a gross reading onto the kink of a robust loss, a limb
// near a singular pose) the linear q_t fit worse than the θ step deserves,
// the trial is rejected and λ grows: the coupled steps then crawl at λ of
// 0.1-20 (the basin test's humanoid under 5% gross readings: the cost still
// falling 1e-6 a step after 200 iterations, "not converged"). So a rejected
// trial is scored again with every q_t refitted to its θ by a few LM steps:
// the cost the θ step is meant to lower, its q_t profiled out. (The q-phase
// keeps the refitted q_t in its box, as the alternation's q-phase does.)
// Returns that cost; `trial` holds the refitted q_t.
double refittedCost(const MeasurementModel& model, const SensorParameters& theta,
                    const NoiseModel& noise, const RobustLoss& loss, const Observations& obs,
                    const FrameOptions& groups, int threads, std::vector<FrameWorkspace>* ws,
                    QState* trial) {
  QPhaseOptions qo;
  qo.method = QPhaseMethod::kLmBatch;
  qo.max_steps = 3;
  qo.threads = threads;
  qo.eval = groups;
  return qPhase(model, theta, noise, loss, obs, qo, ws, trial);
}

// The reduced curvature S costs O(dof·nf²) per frame, the rest O(dof²):
// on a long log S comes from frames spread over it, scaled up, while the
// gradient and the back-substitution use every frame. S is then slightly
// off (a quasi-Newton step, still converging fast), the gradient exact, so
// the fixed point is the true optimum.
struct CurvatureSample {
  bool sampled = false;  // fewer frames than the log's
  Observations obs;      // the spread frames (when sampled)
  RowMatrix q;           // their q_t
  double scale = 1;      // frames of the log per sampled frame
  CurvatureSample(const Observations& all, const RowMatrix& all_q) {
    const int T = all.num_frames;
    const std::vector<int> sample = spreadFrames(T, kCurvatureFrames);
    sampled = static_cast<int>(sample.size()) < T;
    scale = static_cast<double>(T) / static_cast<double>(sample.size());
    if (!sampled) return;
    obs = selectFrames(all, sample);
    q.resize(static_cast<Eigen::Index>(sample.size()), all_q.cols());
    for (size_t i = 0; i < sample.size(); ++i) q.row(i) = all_q.row(sample[i]);
  }
};

}  // namespace

double coupledStep(const MeasurementModel& model, const NoiseModel& noise,
                   const RobustLoss& loss, const Observations& obs, int threads,
                   std::vector<FrameWorkspace>* ws, double* lambda,
                   SensorParameters* theta, QState* state,
                   const CoupledStepOptions& options) {
  const FrameOptions& groups = options.groups;
  threads = std::min<int>(resolveThreads(threads), static_cast<int>(ws->size()));
  const ThetaSpace& space = model.thetaSpace();
  const int nf = space.freeSize();
  const std::vector<int>& free_of = space.freePosition();
  Eigen::VectorXd lower, upper;
  widenedLimits(model.robot(), &lower, &upper);
  const CurvatureSample sample(obs, state->q);
  const std::vector<double> pivots =
      options.inverse_charts ? potPivots(obs) : std::vector<double>();
  double old_cost = -1;
  for (int attempt = 0; attempt < 6; ++attempt) {
    // Every attempt starts from the same (θ, q): the visitor sees it once.
    const FrameVisitor none;
    const FrameVisitor& first = attempt == 0 ? options.visit : none;
    Eigen::VectorXd unreduced_diag;  // for the pots' charts
    Eigen::VectorXd* D = options.inverse_charts ? &unreduced_diag : nullptr;
    ReducedSystem rs = reduceOntoTheta(
        model, *theta, noise, loss, sample.sampled ? sample.obs : obs,
        sample.sampled ? sample.q : state->q, *lambda, !sample.sampled, threads, ws, groups,
        sample.sampled ? none : first, nullptr, D);
    if (sample.sampled) {
      rs.S *= sample.scale;
      if (D) *D *= sample.scale;
      rs.g = reducedGradient(model, *theta, noise, loss, obs, state->q, *lambda, free_of, nf,
                             threads, ws, groups, first, &rs.cost);
    }
    addOriginPrior(space, *theta, &rs.S, &rs.g);  // MAP: the same posterior as every solver
    rs.cost += originPriorCost(space, *theta);
    if (old_cost < 0) old_cost = rs.cost;
    // Pots that dominate their joint move in their inverse chart
    // (pot_chart.hpp), damped there.
    const PotCharts charts = D ? PotCharts(space, *theta, rs.S, *D, pivots) : PotCharts(space);
    charts.toChart(&rs.S, &rs.g);
    Eigen::MatrixXd A = rs.S;
    addScaleFreeDamping(*lambda, rs.S, &A);
    const Eigen::VectorXd dchart = nf > 0 ? Eigen::VectorXd(A.ldlt().solve(-rs.g))
                                          : Eigen::VectorXd();
    if (!dchart.allFinite()) return old_cost;
    const Eigen::VectorXd dfull = space.expandFree(charts.linearStep(dchart));
    RowMatrix q_new = backSubstitute(model, *theta, noise, loss, obs, state->q, dfull, nf > 0,
                                     *lambda, groups, options.within_limits ? &lower : nullptr,
                                     &upper, threads, ws);
    const SensorParameters theta_new = charts.retract(*theta, dchart);
    QState trial;
    trial.q = q_new;
    double c = totalCost(model, theta_new, noise, loss, obs, groups, threads, ws, &trial) +
               originPriorCost(space, theta_new);
    if (options.refit_rejected && !(c < old_cost)) {
      c = refittedCost(model, theta_new, noise, loss, obs, groups, threads, ws, &trial) +
          originPriorCost(space, theta_new);
      q_new = std::move(trial.q);
    }
    if (c < old_cost) {
      *theta = theta_new;
      state->q = std::move(q_new);
      *lambda = acceptedStep(kCoupledSchedule, *lambda);
      return c;
    }
    *lambda = rejectedStep(kCoupledSchedule, *lambda);
  }
  return old_cost;
}

}  // namespace stac
