#include "solve/origin_phase.hpp"

#include <Eigen/Cholesky>
#include <algorithm>

#include "solve/lm_damping.hpp"
#include "solve/origin_prior.hpp"
#include "solve/parallel.hpp"
#include "solve/schur.hpp"

namespace stac {
namespace {

struct ThetaSystem {
  Eigen::MatrixXd H;  // Σ J_θᵀ J_θ over the free entries (+ prior)
  Eigen::VectorXd g;
  double cost = 0;    // data + prior
};

// One pass over the frames at q: the cost and, with `system`, J_θᵀ J_θ and
// J_θᵀ r over the free entries, prior included.
ThetaSystem thetaSystem(const MeasurementModel& model, const SensorParameters& theta,
                        const NoiseModel& noise, const RobustLoss& loss, const Observations& obs,
                        const RowMatrix& q, bool system, int threads,
                        std::vector<FrameWorkspace>* ws) {
  const ThetaSpace& space = model.thetaSpace();
  const int nf = space.freeSize();
  const std::vector<int>& free_of = space.freePosition();
  const int T = obs.num_frames;
  const int blocks = kReductionBlocks;
  std::vector<ThetaSystem> part(blocks);
  FrameOptions eo;
  eo.jacobians = false;
  eo.theta_jacobians = system;
  parallelFor(blocks, threads, [&](int block, int tid) {
    ThetaSystem& p = part[block];
    if (system) p.H.setZero(nf, nf), p.g.setZero(nf);
    FrameWorkspace& w = (*ws)[tid];
    Eigen::VectorXd qt(model.dof());
    const int begin = static_cast<int>(static_cast<long>(T) * block / blocks);
    const int end = static_cast<int>(static_cast<long>(T) * (block + 1) / blocks);
    for (int t = begin; t < end; ++t) {
      qt = q.row(t).transpose();
      p.cost += evaluateFrame(model, theta, noise, loss, frameReadings(obs, t), qt, eo, &w);
      if (!system) continue;
      for (int i = 0; i < w.count; ++i)
        accumulateThetaNormalEquations(w.readings[i], free_of, &p.H, &p.g);
    }
  });
  ThetaSystem out;
  if (system) out.H.setZero(nf, nf), out.g.setZero(nf);
  for (const ThetaSystem& p : part) {
    out.cost += p.cost;
    if (system) out.H += p.H, out.g += p.g;
  }
  out.cost += originPriorCost(space, theta);
  if (!system) return out;
  out.H = out.H.selfadjointView<Eigen::Lower>();
  addOriginPrior(space, theta, &out.H, &out.g);
  return out;
}

}  // namespace

double originPhase(const MeasurementModel& model, const NoiseModel& noise, const RobustLoss& loss,
                   const Observations& obs, const RowMatrix& q, int steps, int threads,
                   std::vector<FrameWorkspace>* ws, double* lambda, SensorParameters* theta) {
  const ThetaSpace& space = model.thetaSpace();
  threads = std::min<int>(resolveThreads(threads), static_cast<int>(ws->size()));
  if (model.sensors().joint_origins.empty() || space.freeSize() == 0) return 0.0;
  ThetaSystem sys = thetaSystem(model, *theta, noise, loss, obs, q, true, threads, ws);
  for (int step = 0, tries = 0; step < steps && tries < 8; ++tries) {
    Eigen::MatrixXd A = sys.H;
    addDamping(*lambda, sys.H, &A);
    const Eigen::VectorXd dx = A.ldlt().solve(-sys.g);
    if (!dx.allFinite()) break;
    const SensorParameters trial = space.plusFree(*theta, dx);
    const double c = thetaSystem(model, trial, noise, loss, obs, q, false, threads, ws).cost;
    if (!(c < sys.cost)) {
      *lambda = rejectedStep(kCoupledSchedule, *lambda);
      continue;
    }
    *theta = trial;
    *lambda = acceptedStep(kCoupledSchedule, *lambda);
    const bool done = sys.cost - c < 1e-10 * sys.cost;
    if (++step == steps || done) return c;
    sys = thetaSystem(model, *theta, noise, loss, obs, q, true, threads, ws);
  }
  return sys.cost;
}

}  // namespace stac
