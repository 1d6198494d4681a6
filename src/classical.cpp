// The classical regression baseline (see classical.hpp).
//
// Parameters β: θ in MeasurementModel's layout, the (gain, bias) slots of
// defining joint sensors holding (a, c), the rotation as a left perturbation.
// Each LM iteration sums the normal equations H = Σ JᵀJ, g = Σ Jᵀr over the
// usable frames (in fixed blocks, so the sums do not depend on the thread
// count) and solves (H + λ diag H) δ = -g over the free entries.
#include "stac/classical.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "stac/calibrate.hpp"
#include "stac/frame_jacobian.hpp"
#include "stac/parallel.hpp"
#include "stac/uncertainty.hpp"
#include "methods/wide_basin.hpp"

namespace stac {

JointSources findJointSources(const RobotModel& robot, const SensorSet& sensors) {
  JointSources out;
  out.sensor.assign(robot.dof(), -1);
  out.defining.assign(sensors.joint_sensors.size(), false);
  for (size_t s = 0; s < sensors.joint_sensors.size(); ++s) {
    const MovableJoint& mj = robot.movableJoints()[sensors.joint_sensors[s].joint];
    if (mj.multiplier == 0.0 || out.sensor[mj.q_index] >= 0) continue;
    out.sensor[mj.q_index] = static_cast<int>(s);
    out.defining[s] = true;
  }
  for (int j = 0; j < robot.dof(); ++j)
    if (out.sensor[j] < 0) out.uncovered.push_back(robot.qName(j));
  return out;
}

InverseMap inverseMap(const GainBias& gb) {
  if (gb.gain == 0.0) return {0.0, 0.0};
  return {1.0 / gb.gain, -gb.bias / gb.gain};
}

GainBias forwardMap(const InverseMap& ic) {
  if (ic.a == 0.0) throw std::domain_error("a joint sensor's fitted inverse gain is zero");
  return {1.0 / ic.a, -ic.c / ic.a};
}

bool anglesFromSensors(const RobotModel& robot, const SensorSet& sensors,
                       const JointSources& sources, const std::vector<InverseMap>& inverse,
                       const double* joint_readings, Eigen::VectorXd* q) {
  q->resize(robot.dof());
  for (int j = 0; j < robot.dof(); ++j) {
    const int s = sources.sensor[j];
    if (s < 0) throw std::invalid_argument("joint " + robot.qName(j) + " has no joint sensor");
    const double p = joint_readings ? joint_readings[s] : NAN;
    if (std::isnan(p)) return false;
    const MovableJoint& mj = robot.movableJoints()[sensors.joint_sensors[s].joint];
    (*q)[j] = (inverse[s].a * p + inverse[s].c - mj.offset) / mj.multiplier;
  }
  return true;
}

bool classicalFrame(const MeasurementModel& model, const JointSources& sources,
                    const ClassicalParameters& params, const NoiseModel& noise,
                    const RobustLoss& loss, const FrameReadings& readings, FrameWorkspace* ws,
                    Eigen::VectorXd* r, Eigen::MatrixXd* J) {
  const RobotModel& robot = model.robot();
  const SensorSet& sensors = model.sensors();
  Eigen::VectorXd q;
  if (!anglesFromSensors(robot, sensors, sources, params.inverse, readings.joint, &q))
    return false;
  EvalOptions eo;
  eo.jacobians = J != nullptr;
  eo.theta_jacobians = J != nullptr;
  evaluateFrame(model, params.theta, noise, loss, readings, q, eo, ws);
  if (!J) {
    int rows = 0;
    for (int i = 0; i < ws->count; ++i) {
      const ReadingJacobian& rj = ws->readings[i];
      if (rj.group != SensorGroup::kJoint || !sources.defining[rj.sensor]) rows += rj.rows;
    }
    r->resize(rows);
    int row = 0;
    for (int i = 0; i < ws->count; ++i) {
      const ReadingJacobian& rj = ws->readings[i];
      if (rj.group == SensorGroup::kJoint && sources.defining[rj.sensor]) continue;
      r->segment(row, rj.rows) = rj.r.head(rj.rows);
      row += rj.rows;
    }
    return true;
  }
  DenseFrame df;
  denseFrame(model, *ws, &sources.defining, &df);
  *r = df.r;
  *J = df.Jtheta;
  // Chain rule through q_j = (a p + c - offset) / multiplier.
  for (int j = 0; j < robot.dof(); ++j) {
    const int s = sources.sensor[j];
    const double p = readings.joint[s];
    const double m = robot.movableJoints()[sensors.joint_sensors[s].joint].multiplier;
    const int o = model.jointOffset(s);
    J->col(o) += df.Jq.col(j) * (p / m);
    J->col(o + 1) += df.Jq.col(j) / m;
  }
  return true;
}

namespace {

using Clock = std::chrono::steady_clock;
constexpr int kBlocks = 16;  // fixed summation blocks: thread-count independent

// β -> β ⊞ δ (full θ layout; zero where not free).
ClassicalParameters retract(const MeasurementModel& model, const JointSources& sources,
                            const ClassicalParameters& p, const Eigen::VectorXd& delta) {
  ClassicalParameters out = p;
  const Eigen::Vector3d d = delta.segment<3>(MeasurementModel::kRotationOffset);
  if (d.norm() > 0)
    out.theta.mocap.rotation =
        (Eigen::Quaterniond(Eigen::AngleAxisd(d.norm(), d.normalized())) * p.theta.mocap.rotation)
            .normalized();
  out.theta.mocap.translation += delta.segment<3>(MeasurementModel::kTranslationOffset);
  const SensorSet& s = model.sensors();
  for (size_t m = 0; m < s.markers.size(); ++m)
    out.theta.marker_position[m] += delta.segment<3>(model.markerOffset(static_cast<int>(m)));
  for (size_t j = 0; j < s.joint_sensors.size(); ++j) {
    const int o = model.jointOffset(static_cast<int>(j));
    if (sources.defining[j]) {
      out.inverse[j].a += delta[o];
      out.inverse[j].c += delta[o + 1];
    } else {
      out.theta.joint_sensor[j].gain += delta[o];
      out.theta.joint_sensor[j].bias += delta[o + 1];
    }
  }
  for (size_t j = 0; j < s.tendon_sensors.size(); ++j) {
    const int o = model.tendonOffset(static_cast<int>(j));
    out.theta.tendon_sensor[j].gain += delta[o];
    out.theta.tendon_sensor[j].bias += delta[o + 1];
  }
  return out;
}

double sigmaOf(const NoiseModel& noise, const ReadingJacobian& rj) {
  switch (rj.group) {
    case SensorGroup::kMarker: return noise.marker[rj.sensor];
    case SensorGroup::kJoint: return noise.joint[rj.sensor];
    case SensorGroup::kTendon: return noise.tendon[rj.sensor];
  }
  return 1.0;
}

// One pass over the usable frames.
struct Pass {
  double cost = 0;
  Eigen::MatrixXd H;  // free x free (with normal equations)
  Eigen::VectorXd g;
  double sse[kNumSensorGroups] = {0, 0, 0};    // raw units²
  double wsse[kNumSensorGroups] = {0, 0, 0};   // Σ ρ'(s) s at the seed σ
  double rows[kNumSensorGroups] = {0, 0, 0};
  double count[kNumSensorGroups] = {0, 0, 0};  // readings
};

class Regression {
 public:
  Regression(const MeasurementModel& model, const JointSources& sources,
             const Observations& obs, const RobustLoss& loss, int threads)
      : model_(model), sources_(sources), obs_(obs), loss_(loss), threads_(threads) {
    for (int i = 0; i < model.thetaSize(); ++i)
      if (model.thetaFree()[i]) free_.push_back(i);
    for (int i = 0; i < threads; ++i) ws_.emplace_back(model);
  }
  const std::vector<int>& freeIndex() const { return free_; }

  Pass pass(const ClassicalParameters& p, const NoiseModel& noise, const NoiseModel& seed_noise,
            bool normal_equations) {
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
          const double sigma = sigmaOf(noise, rj), ratio = sigma / sigmaOf(seed_noise, rj);
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
    if (normal_equations) total.H = total.H.selfadjointView<Eigen::Lower>();
    return total;
  }

  // Levenberg-Marquardt from *p; returns iterations, sets *converged.
  int solve(const NoiseModel& noise, const NoiseModel& seed_noise,
            const CalibrationOptions& options, Clock::time_point start, int first_iteration,
            ClassicalParameters* p, bool* converged) {
    const int nf = static_cast<int>(free_.size());
    *converged = false;
    if (nf == 0) {
      *converged = true;
      return 0;
    }
    Pass cur = pass(*p, noise, seed_noise, true);
    double lambda = 1e-4;
    int it = 0;
    Eigen::VectorXd delta_full = Eigen::VectorXd::Zero(model_.thetaSize());
    while (it < options.max_iterations) {
      ++it;
      bool accepted = false;
      double rel = 0;
      for (int attempt = 0; attempt < 12 && !accepted; ++attempt) {
        Eigen::MatrixXd A = cur.H;
        const double eps = 1e-12 * std::max(1.0, cur.H.diagonal().maxCoeff());
        for (int i = 0; i < nf; ++i) A(i, i) += lambda * cur.H(i, i) + eps;
        const Eigen::VectorXd step = A.ldlt().solve(-cur.g);
        if (!step.allFinite()) {
          lambda *= 10;
          continue;
        }
        delta_full.setZero();
        for (int i = 0; i < nf; ++i) delta_full[free_[i]] = step[i];
        const ClassicalParameters trial = retract(model_, sources_, *p, delta_full);
        const Pass next = pass(trial, noise, seed_noise, false);
        if (std::isfinite(next.cost) && next.cost < cur.cost) {
          rel = (cur.cost - next.cost) / std::max(cur.cost, 1e-300);
          *p = trial;
          lambda = std::max(lambda / 3.0, 1e-12);
          accepted = true;
        } else {
          lambda = std::min(lambda * 4.0, 1e12);
        }
      }
      if (!accepted) {
        *converged = true;  // no descent left at any damping: a minimum
        break;
      }
      cur = pass(*p, noise, seed_noise, true);
      if (options.progress) {
        IterationReport r;
        r.iteration = first_iteration + it;
        r.cost = cur.cost;
        for (int g = 0; g < kNumSensorGroups; ++g) {
          r.present[g] = cur.count[g] > 0;
          r.rms[g] = cur.count[g] > 0 ? std::sqrt(cur.sse[g] / cur.count[g]) : 0.0;
        }
        r.elapsed = std::chrono::duration<double>(Clock::now() - start).count();
        r.stage = "classical";
        options.progress(r);
      }
      if (rel < options.tolerance) {
        *converged = true;
        break;
      }
    }
    last_ = cur;
    return it;
  }

  const Pass& last() const { return last_; }

 private:
  const MeasurementModel& model_;
  const JointSources& sources_;
  const Observations& obs_;
  const RobustLoss& loss_;
  int threads_;
  std::vector<int> free_;
  std::vector<FrameWorkspace> ws_;
  Pass last_;
};

std::string joinNames(const std::vector<std::string>& v) {
  std::string s;
  for (const std::string& x : v) s += (s.empty() ? "" : ", ") + x;
  return s;
}

}  // namespace

CalibrationResult calibrateClassical(const RobotModel& robot, const SensorSet& sensors,
                                     const SensorParameters& seed, const Observations& obs,
                                     const CalibrationOptions& options,
                                     RowMatrix* joint_angles) {
  std::string error;
  if (!options.isValid(&error)) throw std::invalid_argument(error);
  if (obs.num_frames < 1) throw std::invalid_argument("the log has no frames");
  const JointSources sources = findJointSources(robot, sensors);
  if (!sources.uncovered.empty())
    throw std::invalid_argument(
        "the classical regression reads every joint angle off a one-joint sensor, but no joint "
        "sensor is on: " + joinNames(sources.uncovered) +
        " (use --method stac, which also handles tendon-only joints)");
  const Clock::time_point start = Clock::now();
  const MeasurementModel model(robot, sensors);
  const NoiseModel seed_noise = NoiseModel::fromSeeds(sensors);
  NoiseModel noise = seed_noise;
  const RobustLoss loss(options.loss, options.loss_scale);
  const int threads = resolveThreads(options.threads);
  const int J = static_cast<int>(sensors.joint_sensors.size());

  // Frames where every defining reading is present; the rest are skipped.
  std::vector<int> usable;
  for (int t = 0; t < obs.num_frames; ++t) {
    bool ok = true;
    for (int j = 0; j < J && ok; ++j) ok = !(sources.defining[j] && std::isnan(obs.joint(t, j)));
    if (ok) usable.push_back(t);
  }
  if (usable.empty())
    throw std::invalid_argument("no frame has every joint sensor's reading");
  const Observations used = selectFrames(obs, usable);

  ClassicalParameters p;
  p.theta = seed;
  p.inverse.resize(J);
  for (int j = 0; j < J; ++j)
    if (sources.defining[j]) p.inverse[j] = inverseMap(seed.joint_sensor[j]);

  CalibrationResult result;
  CalibrationSummary& summary = result.summary;
  summary.method = "classical";
  summary.frames = used.num_frames;
  fittedResidualRms(model, seed, noise, loss, obs,
                    neutralPose(robot).transpose().replicate(obs.num_frames, 1), threads,
                    summary.before_rms);

  Regression reg(model, sources, used, loss, threads);
  // Variance adaptation (paper §III-E) between solves: one σ scale per
  // group of fitted readings. With one group only, σ does not move the
  // optimum, so one solve suffices.
  double kappa[kNumSensorGroups] = {1, 1, 1};
  int iterations = 0;
  bool converged = false;
  int groups = 0;
  {
    const Pass first = reg.pass(p, noise, seed_noise, false);
    summary.initial_cost = first.cost;
    for (int g = 0; g < kNumSensorGroups; ++g) groups += first.count[g] > 0;
  }
  const int n_free = static_cast<int>(reg.freeIndex().size());
  for (int round = 0; round < 5; ++round) {
    iterations += reg.solve(noise, seed_noise, options, start, iterations, &p, &converged);
    if (!options.adapt_variance) break;
    const Pass& st = reg.last();
    double total_rows = 0;
    for (int g = 0; g < kNumSensorGroups; ++g) total_rows += st.rows[g];
    // Each group's share of the fitted parameters' degrees of freedom.
    const double keep = total_rows > n_free ? 1.0 - n_free / total_rows : 1.0;
    double change = 0;
    for (int g = 0; g < kNumSensorGroups; ++g) {
      if (st.rows[g] == 0) continue;
      const double k = std::max(std::sqrt(st.wsse[g] / (st.rows[g] * keep)), 1e-9);
      change = std::max(change, std::abs(k - kappa[g]) / kappa[g]);
      kappa[g] = k;
    }
    noise = seed_noise;
    for (double& s : noise.marker) s *= kappa[0];
    for (size_t j = 0; j < noise.joint.size(); ++j)
      if (!sources.defining[j]) noise.joint[j] *= kappa[1];
    for (double& s : noise.tendon) s *= kappa[2];
    if (groups <= 1 || change < 1e-3) break;
  }
  // Statistics at the final σ.
  const Pass fin = reg.pass(p, noise, seed_noise, true);

  // Back to (gain, bias) and the information in MeasurementModel's layout:
  // (a, c) = (1/g, -b/g), so d(a, c)/d(g, b) = [[-1/g², 0], [b/g², -1/g]].
  SensorParameters theta = p.theta;
  const std::vector<int>& free = reg.freeIndex();
  Eigen::MatrixXd Tgb = Eigen::MatrixXd::Identity(free.size(), free.size());
  for (int j = 0; j < J; ++j) {
    if (!sources.defining[j]) continue;
    theta.joint_sensor[j] = forwardMap(p.inverse[j]);
    const auto it = std::find(free.begin(), free.end(), model.jointOffset(j));
    if (it == free.end()) continue;  // fixed sensor
    const int k = static_cast<int>(it - free.begin());
    const double g = theta.joint_sensor[j].gain, b = theta.joint_sensor[j].bias;
    Tgb(k, k) = -1.0 / (g * g);
    Tgb(k + 1, k) = b / (g * g);
    Tgb(k + 1, k + 1) = -1.0 / g;
  }
  const Eigen::MatrixXd info = Tgb.transpose() * fin.H * Tgb;
  const UncertaintyResult unc = uncertaintyFromInformation(model, theta, info);

  result.sensors = sensors;
  for (size_t m = 0; m < sensors.markers.size(); ++m)
    result.sensors.markers[m].sigma = noise.marker[m];
  for (int j = 0; j < J; ++j) result.sensors.joint_sensors[j].sigma = noise.joint[j];
  for (size_t j = 0; j < sensors.tendon_sensors.size(); ++j)
    result.sensors.tendon_sensors[j].sigma = noise.tendon[j];
  if (!sensors.markers.empty()) result.sensors.mocap_sigma = sensors.mocap_sigma * kappa[0];
  result.theta = theta;
  result.std = toParameterStd(model, unc.std);

  // q from the sensors for every frame (NaN where a reading is missing).
  RowMatrix q(obs.num_frames, robot.dof());
  for (int t = 0; t < obs.num_frames; ++t)
    for (int j = 0; j < robot.dof(); ++j) {
      const int s = sources.sensor[j];
      const MovableJoint& mj = robot.movableJoints()[sensors.joint_sensors[s].joint];
      q(t, j) = (p.inverse[s].a * obs.joint(t, s) + p.inverse[s].c - mj.offset) / mj.multiplier;
    }
  RowMatrix q_used(used.num_frames, robot.dof());
  for (int k = 0; k < used.num_frames; ++k) q_used.row(k) = q.row(usable[k]);
  residualStatistics(model, theta, used, q_used, threads, &result);

  summary.iterations = iterations;
  summary.converged = converged;
  summary.final_cost = fin.cost;
  for (int g = 0; g < kNumSensorGroups; ++g)
    summary.after_rms[g] = fin.count[g] > 0 ? std::sqrt(fin.sse[g] / fin.count[g]) : 0.0;
  summary.unidentifiable = unc.unidentifiable;
  // Defining joint sensors have σ_p -> 0 by construction (their seed σ is
  // kept in the sensors so the file feeds back); report the others'.
  summariseGroupNoise(sensors, noise, &summary, &sources.defining);
  summary.wall_time = std::chrono::duration<double>(Clock::now() - start).count();
  if (joint_angles) *joint_angles = q;
  return result;
}

}  // namespace stac
