// The EKF baseline (see ekf.hpp). Frame by frame:
//   predict:  P_qq += Σ_q                                  (eq. 24)
//   linearise every reading at (θ, q):  r (whitened), H = [dr/dθ_free, dr/dq]
//                                                          (eq. 25-27)
//   update:   S = H P Hᵀ + I,  K = P Hᵀ S⁻¹,  dx = -K r,  P -= K S Kᵀ
// Readings are whitened by σ, so the observation covariance is I. The update
// is applied additively except for the mocap rotation (R <- exp([δ]x) R);
// its covariance stays in the tangent space (the reset Jacobian I - ½[δ]x is
// taken as I, as usual for small updates).
#include "methods/method.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <set>

#include "solve/pass.hpp"
#include "solve/statistics.hpp"
#include "stac/error.hpp"
#include "model/frame_jacobian.hpp"
#include "solve/parallel.hpp"
#include "solve/q_phase.hpp"
#include "stac/simulate.hpp"
#include "solve/uncertainty.hpp"

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

namespace {

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
  Eigen::VectorXd sd(model.thetaSpace().size());
  sd.segment<3>(ThetaSpace::kRotationOffset).setConstant(o.rotation_std);
  sd.segment<3>(ThetaSpace::kTranslationOffset).setConstant(o.translation_std);
  const SensorSet& s = model.sensors();
  for (size_t m = 0; m < s.markers.size(); ++m)
    sd.segment<3>(model.thetaSpace().markerOffset(static_cast<int>(m))).setConstant(o.marker_std);
  for (size_t j = 0; j < s.joint_sensors.size(); ++j) {
    const double g = std::max(std::abs(seed.joint_sensor[j].gain), 1.0);
    sd[model.thetaSpace().jointOffset(static_cast<int>(j))] = o.gain_std * g;
    sd[model.thetaSpace().jointOffset(static_cast<int>(j)) + 1] = o.joint_bias_std * g;
  }
  for (size_t j = 0; j < s.tendon_sensors.size(); ++j) {
    const double g = std::max(std::abs(seed.tendon_sensor[j].gain), 1.0);
    sd[model.thetaSpace().tendonOffset(static_cast<int>(j))] = o.gain_std * g;
    sd[model.thetaSpace().tendonOffset(static_cast<int>(j)) + 1] = o.tendon_bias_std * g;
  }
  return sd * o.theta_std_scale;
}


// The filter's state [free θ; q] and covariance P over it.
struct Filter {
  SensorParameters theta;
  Eigen::VectorXd q;
  Eigen::MatrixXd P;
};

// q_0: given (paper §VI-B: the truth), or frame 0 solved at the seed θ;
// clamped into the q-phase's box. *q_std receives its std per joint.
Eigen::VectorXd initialAngles(const MethodInput& in, const Eigen::VectorXd& span,
                              Eigen::VectorXd* q_std, Workspaces* ws) {
  const EkfOptions& eo = in.options.ekf;
  const Problem& problem = in.problem;
  const RobotModel& robot = problem.model.robot();
  const int dof = robot.dof();
  Eigen::VectorXd q(dof);
  q_std->resize(dof);
  if (eo.initial_q.size() == dof) {
    q = eo.initial_q;
    q_std->setConstant(eo.initial_q_std);
  } else {
    QState first;
    first.q = neutralPose(robot).transpose();
    QPhaseOptions qo;
    qo.method = QPhaseMethod::kLmBatch;
    qo.max_steps = 100;
    qo.threads = 1;
    qPhase(problem.model, in.seed, problem.seed_noise, problem.loss,
           sliceFrames(problem.obs, 0, 1), qo, ws, &first);
    q = first.q.row(0).transpose();
    *q_std = eo.solved_q_std_fraction * span;
  }
  Eigen::VectorXd lower, upper;
  widenedLimits(robot, &lower, &upper);
  return q.cwiseMax(lower).cwiseMin(upper);
}

// Scratch of the measurement update.
struct UpdateScratch {
  DenseFrame df;
  Eigen::MatrixXd H, PHt, S, K;
  Eigen::VectorXd dx, dx_total;
};

// The update of frame t (its readings already evaluated in w at the
// filter's state); with iterations > 1 the iterated EKF: relinearise at the
// updated state x_i and redo the update from the prediction x̄,
//   x_{i+1} = x̄ + K_i (-r_i + H_i (x_i - x̄)),
// Gauss-Newton on this frame's posterior (the plain EKF is i = 0 only).
// Returns false if the update is not finite.
bool updateFrame(const Problem& problem, const EkfOptions& eo, int t, const Eigen::VectorXd& lower,
                 const Eigen::VectorXd& upper, Filter* f, FrameWorkspace* w, UpdateScratch* u) {
  const MeasurementModel& model = problem.model;
  const ThetaSpace& space = model.thetaSpace();
  const std::vector<int>& free_index = space.freeIndex();
  const int nf = space.freeSize(), dof = model.dof(), n = nf + dof;
  FrameOptions ev;
  ev.jacobians = true;
  ev.theta_jacobians = true;
  const SensorParameters theta_prior = f->theta;
  const Eigen::VectorXd q_prior = f->q;
  u->dx_total.setZero(n);
  for (int it = 0; it < eo.iterations; ++it) {
    if (it > 0)
      evaluateFrame(model, f->theta, problem.seed_noise, problem.loss,
                    frameReadings(problem.obs, t), f->q, ev, w);
    denseFrame(model, *w, nullptr, &u->df);
    if (u->df.rows == 0) break;
    u->H.resize(u->df.rows, n);
    for (int i = 0; i < nf; ++i) u->H.col(i) = u->df.Jtheta.col(free_index[i]);
    u->H.rightCols(dof) = u->df.Jq;
    u->PHt.noalias() = f->P * u->H.transpose();
    u->S.noalias() = u->H * u->PHt;
    u->S.diagonal().array() += 1.0;
    Eigen::LLT<Eigen::MatrixXd> llt(u->S);
    u->K = llt.solve(u->PHt.transpose()).transpose();  // P Hᵀ S⁻¹ (S symmetric)
    u->dx.noalias() = u->K * (u->H * u->dx_total - u->df.r);
    if (!u->dx.allFinite() || llt.info() != Eigen::Success) return false;
    const double change = (u->dx - u->dx_total).norm();
    f->theta = space.plusFree(theta_prior, u->dx.head(nf));
    f->q = (q_prior + u->dx.tail(dof)).cwiseMax(lower).cwiseMin(upper);
    u->dx_total = u->dx;
    u->dx_total.tail(dof) = f->q - q_prior;
    if (it + 1 == eo.iterations || change < 1e-10 * (1.0 + u->dx.norm())) {
      f->P.noalias() -= u->K * u->PHt.transpose();
      f->P = 0.5 * (f->P + f->P.transpose()).eval();
      break;
    }
  }
  return true;
}

// The forward pass over every frame; returns false if it stopped on a
// non-finite update (the remaining frames keep the last q). Progress: one
// report per ~10% of the frames on the innovations of that stretch.
bool forwardPass(const MethodInput& in, const Eigen::VectorXd& process_var, Filter* f,
                 RowMatrix* filtered, Workspaces* ws) {
  const Problem& problem = in.problem;
  const int T = problem.obs.num_frames, dof = problem.model.dof();
  Eigen::VectorXd lower, upper;
  widenedLimits(problem.model.robot(), &lower, &upper);
  FrameOptions ev;
  ev.jacobians = true;
  ev.theta_jacobians = true;
  FrameWorkspace& w = (*ws)[0];
  UpdateScratch u;
  PassStats stretch;
  const int report_every = std::max(1, (T + 9) / 10);
  for (int t = 0; t < T; ++t) {
    if (t > 0) f->P.diagonal().tail(dof) += process_var;
    stretch.cost += evaluateFrame(problem.model, f->theta, problem.seed_noise, problem.loss,
                                  frameReadings(problem.obs, t), f->q, ev, &w);
    for (int i = 0; i < w.count; ++i) {
      const ReadingJacobian& rj = w.readings[i];
      const double sigma = problem.seed_noise.sigma(rj.group, rj.sensor);
      stretch.sse[static_cast<int>(rj.group)] += rj.s * sigma * sigma;
      stretch.count[static_cast<int>(rj.group)] += 1;
    }
    if (!updateFrame(problem, in.options.ekf, t, lower, upper, f, &w, &u) || !f->P.allFinite()) {
      filtered->bottomRows(T - t).rowwise() = f->q.transpose();
      return false;
    }
    filtered->row(t) = f->q.transpose();
    if (in.options.progress && ((t + 1) % report_every == 0 || t + 1 == T)) {
      const int report = (t + report_every) / report_every;
      in.options.progress(makeReport(report, stretch, in.start, "ekf"));
      stretch = PassStats();
    }
  }
  return true;
}

// The filter's prior: the seed's std on the free θ entries, q_std on q.
Eigen::MatrixXd priorCovariance(const MethodInput& in, const Eigen::VectorXd& q_std) {
  const ThetaSpace& space = in.problem.model.thetaSpace();
  const int nf = space.freeSize(), dof = in.problem.model.dof();
  const Eigen::VectorXd theta_std = seedStd(in.problem.model, in.seed, in.options.ekf);
  Eigen::MatrixXd P = Eigen::MatrixXd::Zero(nf + dof, nf + dof);
  for (int i = 0; i < nf; ++i)
    P(i, i) = theta_std[space.freeIndex()[i]] * theta_std[space.freeIndex()[i]];
  for (int j = 0; j < dof; ++j) P(nf + j, nf + j) = q_std[j] * q_std[j];
  return P;
}

// Uncertainty: the filter's own covariance, except that directions the
// data cannot determine (at the final θ and the filtered q_t) are listed
// and get an infinite std rather than the prior's.
UncertaintyResult filterUncertainty(const Problem& problem, const Filter& f,
                                    const RowMatrix& filtered, Workspaces* ws) {
  const ThetaSpace& space = problem.model.thetaSpace();
  UncertaintyResult unc = estimateUncertainty(problem.model, f.theta, problem.seed_noise,
                                              problem.loss, problem.obs, filtered,
                                              problem.threads, ws);
  std::set<std::string> unidentified;
  for (const UnidentifiableDirection& d : unc.unidentifiable)
    unidentified.insert(d.parameters.begin(), d.parameters.end());
  unc.std.setZero(space.size());
  for (int i = 0; i < space.freeSize(); ++i)
    unc.std[space.freeIndex()[i]] = std::sqrt(std::max(f.P(i, i), 0.0));
  for (int i = 0; i < space.size(); ++i)
    if (unidentified.count(space.names()[i])) unc.std[i] = std::numeric_limits<double>::infinity();
  return unc;
}

}  // namespace

Outcome runEkf(const MethodInput& in) {
  const Problem& problem = in.problem;
  const EkfOptions& eo = in.options.ekf;
  const RobotModel& robot = problem.model.robot();
  const int T = problem.obs.num_frames, dof = robot.dof();
  if (eo.initial_q.size() != 0 && eo.initial_q.size() != dof)
    throw std::invalid_argument("EKF initial joint angles: expected " + std::to_string(dof) +
                                " values");
  Workspaces ws = makeWorkspaces(problem.model, problem.threads);
  const std::vector<JointRange> range = motionRanges(robot);
  Eigen::VectorXd span(dof);
  for (int j = 0; j < dof; ++j) span[j] = range[j].upper - range[j].lower;

  Filter f;
  f.theta = in.seed;
  Eigen::VectorXd q_std;
  f.q = initialAngles(in, span, &q_std, &ws);
  f.P = priorCovariance(in, q_std);
  const double dt = 1.0 / frameRate(problem.obs, eo.rate_hz);
  const Eigen::VectorXd process_var = (eo.q_speed * dt * span).array().square();

  Outcome out;
  const RowMatrix q_start = f.q.transpose().replicate(T, 1);
  fittedResidualRms(problem, in.seed, q_start, out.before_rms);
  out.initial_cost = costPass(problem, in.seed, problem.seed_noise, q_start, false, &ws).cost;
  RowMatrix filtered(T, dof);
  out.converged = forwardPass(in, process_var, &f, &filtered, &ws);
  out.iterations = 1;  // one forward pass
  out.uncertainty = filterUncertainty(problem, f, filtered, &ws);
  const PassStats fin = costPass(problem, f.theta, problem.seed_noise, filtered, false, &ws);
  out.final_cost = fin.cost;
  for (int g = 0; g < kNumSensorGroups; ++g) out.after_rms[g] = fin.rms(g);
  out.theta = f.theta;
  out.noise = problem.seed_noise;
  out.q = std::move(filtered);
  return out;
}

}  // namespace stac
