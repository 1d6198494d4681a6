// The classical regression's Levenberg-Marquardt core (see regression.hpp
// and classical.cpp's header comment for the parameters β).
#include "methods/regression.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>

#include "solve/lm_damping.hpp"
#include "solve/origin_prior.hpp"
#include "solve/parallel.hpp"
#include "solve/pass.hpp"

namespace stac {
namespace {

constexpr int kBlocks = 16;  // fixed summation blocks: thread-count independent

// β -> β ⊞ δ (full θ layout; zero where not free): θ's own entries by the θ
// space, the (a, c) held in the slots of defining joint sensors added here.
ClassicalParameters retract(const ThetaSpace& space, const JointSources& sources,
                            const ClassicalParameters& p, const Eigen::VectorXd& delta) {
  ClassicalParameters out = p;
  Eigen::VectorXd theta_delta = delta;
  for (size_t j = 0; j < sources.defining.size(); ++j) {
    if (!sources.defining[j]) continue;
    const int o = space.jointOffset(static_cast<int>(j));
    out.inverse[j].a += delta[o];
    out.inverse[j].c += delta[o + 1];
    if (tiedOffset(space.sensors().joint_sensors[j].fixed))
      out.inverse[j].c = -p.theta.joint_sensor[j].bias * out.inverse[j].a;
    theta_delta[o] = theta_delta[o + 1] = 0.0;
  }
  out.theta = space.plus(p.theta, theta_delta);
  return out;
}

}  // namespace

Regression::Regression(const MeasurementModel& model, const JointSources& sources,
                       const Observations& obs, const RobustLoss& loss, int threads)
    : model_(model), sources_(sources), obs_(obs), loss_(loss), threads_(threads),
      free_(model.thetaSpace().freeIndex()) {
  for (int i = 0; i < threads; ++i) ws_.emplace_back(model);
}

Pass Regression::pass(const ClassicalParameters& p, const NoiseModel& noise,
                      const NoiseModel& seed_noise, bool normal_equations) {
  const int nf = static_cast<int>(free_.size());
  const int T = obs_.num_frames;
  std::vector<Pass> blocks(kBlocks);
  parallelFor(kBlocks, threads_, [&](int b, int tid) {
    Pass& out = blocks[b];
    if (normal_equations) out.H.setZero(nf, nf), out.g.setZero(nf);
    FrameWorkspace& w = ws_[tid];
    Eigen::VectorXd r;
    Eigen::MatrixXd J, Jf;
    const int begin = static_cast<int>(static_cast<long>(T) * b / kBlocks);
    const int end = static_cast<int>(static_cast<long>(T) * (b + 1) / kBlocks);
    for (int t = begin; t < end; ++t) {
      if (!classicalFrame(model_, sources_, p, noise, loss_, frameReadings(obs_, t), &w, &r,
                          normal_equations ? &J : nullptr))
        continue;
      out.cost += 0.5 * r.squaredNorm();
      for (int i = 0; i < w.count; ++i) {
        const ReadingJacobian& rj = w.readings[i];
        if (rj.group == SensorGroup::kJoint && sources_.defining[rj.sensor]) continue;
        const int g = static_cast<int>(rj.group);
        const double sigma = noise.sigma(rj.group, rj.sensor);
        const double ratio = sigma / seed_noise.sigma(rj.group, rj.sensor);
        out.sse[g] += rj.s * sigma * sigma;
        out.wsse[g] += rj.weight * rj.s * ratio * ratio;
        out.rows[g] += rj.rows;
        out.count[g] += 1;
      }
      if (!normal_equations || r.size() == 0) continue;
      Jf.resize(r.size(), nf);
      for (int i = 0; i < nf; ++i) Jf.col(i) = J.col(free_[i]);
      out.H.selfadjointView<Eigen::Lower>().rankUpdate(Jf.transpose());
      out.g.noalias() += Jf.transpose() * r;
    }
  });
  Pass total;
  if (normal_equations) total.H.setZero(nf, nf), total.g.setZero(nf);
  for (const Pass& b : blocks) {
    total.cost += b.cost;
    if (normal_equations) total.H += b.H, total.g += b.g;
    for (int g = 0; g < kNumSensorGroups; ++g) {
      total.sse[g] += b.sse[g];
      total.wsse[g] += b.wsse[g];
      total.rows[g] += b.rows[g];
      total.count[g] += b.count[g];
    }
  }
  // The joint-origin prior (MAP), as in every solver (origin_prior.hpp).
  const ThetaSpace& space = model_.thetaSpace();
  total.cost += originPriorCost(space, p.theta);
  if (normal_equations) {
    total.H = total.H.selfadjointView<Eigen::Lower>();
    addOriginPrior(space, p.theta, &total.H, &total.g);
  }
  return total;
}

int Regression::solve(const NoiseModel& noise, const NoiseModel& seed_noise,
                      const CalibrationOptions& options, Clock::time_point start,
                      int first_iteration, ClassicalParameters* p, bool* converged) {
  const int nf = static_cast<int>(free_.size());
  *converged = false;
  if (nf == 0) {
    *converged = true;
    return 0;
  }
  Pass cur = pass(*p, noise, seed_noise, true);
  double lambda = 1e-4;
  int it = 0;
  while (it < options.max_iterations) {
    ++it;
    bool accepted = false;
    double rel = 0;
    for (int attempt = 0; attempt < 12 && !accepted; ++attempt) {
      Eigen::MatrixXd A = cur.H;
      addDamping(lambda, cur.H, &A);
      const Eigen::VectorXd step = A.ldlt().solve(-cur.g);
      if (!step.allFinite()) {
        lambda = rejectedStep(kRegressionSchedule, lambda);
        continue;
      }
      const ClassicalParameters trial = retract(model_.thetaSpace(), sources_, *p,
                                                model_.thetaSpace().expandFree(step));
      const Pass next = pass(trial, noise, seed_noise, false);
      if (std::isfinite(next.cost) && next.cost < cur.cost) {
        rel = (cur.cost - next.cost) / std::max(cur.cost, 1e-300);
        *p = trial;
        lambda = acceptedStep(kRegressionSchedule, lambda);
        accepted = true;
      } else {
        lambda = rejectedStep(kRegressionSchedule, lambda);
      }
    }
    if (!accepted) {
      *converged = true;  // no descent left at any damping: a minimum
      break;
    }
    cur = pass(*p, noise, seed_noise, true);
    if (options.progress) {
      PassStats report;
      report.cost = cur.cost;
      std::copy(cur.sse, cur.sse + kNumSensorGroups, report.sse);
      std::copy(cur.count, cur.count + kNumSensorGroups, report.count);
      options.progress(makeReport(first_iteration + it, report, start, "classical"));
    }
    if (rel < options.tolerance) {
      *converged = true;
      break;
    }
  }
  last_ = cur;
  return it;
}

}  // namespace stac
