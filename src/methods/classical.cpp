// The classical regression baseline (see classical.hpp).
//
// Parameters β: θ in MeasurementModel's layout, the (gain, bias) slots of
// defining joint sensors holding (a, c), the rotation as a left perturbation.
// Each LM iteration sums the normal equations H = Σ JᵀJ, g = Σ Jᵀr over the
// usable frames (in fixed blocks, so the sums do not depend on the thread
// count) and solves (H + λ diag H) δ = -g over the free entries.
#include "methods/classical.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "methods/method.hpp"
#include "methods/regression.hpp"
#include "solve/pass.hpp"
#include "solve/statistics.hpp"
#include "model/frame_jacobian.hpp"
#include "solve/lm_damping.hpp"
#include "solve/noise_adaptation.hpp"
#include "solve/origin_prior.hpp"
#include "solve/parallel.hpp"
#include "solve/uncertainty.hpp"

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

std::vector<int> framesWithEveryDefiningReading(const Observations& obs,
                                                const JointSources& sources) {
  std::vector<int> usable;
  const int J = static_cast<int>(sources.defining.size());
  for (int t = 0; t < obs.num_frames; ++t) {
    bool ok = true;
    for (int j = 0; j < J && ok; ++j) ok = !(sources.defining[j] && std::isnan(obs.joint(t, j)));
    if (ok) usable.push_back(t);
  }
  return usable;
}

RowMatrix anglesOfEveryFrame(const RobotModel& robot, const SensorSet& sensors,
                             const JointSources& sources, const ClassicalParameters& p,
                             const Observations& obs) {
  RowMatrix q(obs.num_frames, robot.dof());
  for (int t = 0; t < obs.num_frames; ++t)
    for (int j = 0; j < robot.dof(); ++j) {
      const int s = sources.sensor[j];
      const MovableJoint& mj = robot.movableJoints()[sensors.joint_sensors[s].joint];
      q(t, j) = (p.inverse[s].a * obs.joint(t, s) + p.inverse[s].c - mj.offset) / mj.multiplier;
    }
  return q;
}

bool tiedOffset(const FixedGainBias& fixed) { return fixed.bias && !fixed.gain; }

bool classicalFrame(const MeasurementModel& model, const JointSources& sources,
                    const ClassicalParameters& params, const NoiseModel& noise,
                    const RobustLoss& loss, const FrameReadings& readings, FrameWorkspace* ws,
                    Eigen::VectorXd* r, Eigen::MatrixXd* J) {
  const RobotModel& robot = model.robot();
  const SensorSet& sensors = model.sensors();
  Eigen::VectorXd q;
  if (!anglesFromSensors(robot, sensors, sources, params.inverse, readings.joint, &q))
    return false;
  FrameOptions eo;
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
  // Chain rule through q_j = (a p + c - offset) / multiplier; a held bias b
  // ties c = -b a, so that a's column carries c's share too.
  for (int j = 0; j < robot.dof(); ++j) {
    const int s = sources.sensor[j];
    const double p = readings.joint[s];
    const double m = robot.movableJoints()[sensors.joint_sensors[s].joint].multiplier;
    const int o = model.thetaSpace().jointOffset(s);
    const double pa = tiedOffset(sensors.joint_sensors[s].fixed)
                          ? p - params.theta.joint_sensor[s].bias
                          : p;
    J->col(o) += df.Jq.col(j) * (pa / m);
    J->col(o + 1) += df.Jq.col(j) / m;
  }
  return true;
}

namespace {

std::string joinNames(const std::vector<std::string>& v) {
  std::string s;
  for (const std::string& x : v) s += (s.empty() ? "" : ", ") + x;
  return s;
}

// Frames where every defining reading is present; the rest are skipped.
std::vector<int> usableFrames(const Observations& obs, const JointSources& sources) {
  std::vector<int> usable = framesWithEveryDefiningReading(obs, sources);
  if (usable.empty()) throw std::invalid_argument("no frame has every joint sensor's reading");
  return usable;
}

// Solves, with variance adaptation (paper §III-E) between solves: one σ
// scale per group of fitted readings. With one group only, σ does not move
// the optimum, so one solve suffices. Returns the iterations.
int solveAdapting(const MethodInput& in, const JointSources& sources, int groups,
                  Regression* reg, ClassicalParameters* p, GroupScales* scales,
                  NoiseModel* noise, bool* converged) {
  const NoiseModel& seed_noise = in.problem.seed_noise;
  const int n_free = static_cast<int>(reg->freeIndex().size());
  int iterations = 0;
  for (int round = 0; round < 5; ++round) {
    iterations += reg->solve(*noise, seed_noise, in.options, in.start, iterations, p, converged);
    if (!in.options.adapt_variance) break;
    const Pass& st = reg->last();
    double total_rows = 0;
    for (int g = 0; g < kNumSensorGroups; ++g) total_rows += st.rows[g];
    // Each group's share of the fitted parameters' degrees of freedom.
    const double keep = total_rows > n_free ? 1.0 - n_free / total_rows : 1.0;
    GroupResiduals residuals;
    for (int g = 0; g < kNumSensorGroups; ++g) {
      residuals.wsse[g] = st.wsse[g];
      residuals.dofs[g] = st.rows[g] * keep;
    }
    const double change = updateScales(residuals, false, scales);
    *noise = scaledNoise(seed_noise, *scales, &sources.defining);
    if (groups <= 1 || change < 1e-3) break;
  }
  return iterations;
}

// Back to (gain, bias) and the information in θ's layout: (a, c) = (1/g,
// -b/g), so d(a, c)/d(g, b) = [[-1/g², 0], [b/g², -1/g]] over the free
// entries (a held bias: a alone, its column already carrying c = -b a; a
// held gain: c alone). Held parts keep their exact given values.
UncertaintyResult toGainBias(const MeasurementModel& model, const JointSources& sources,
                             const ClassicalParameters& p, const Eigen::MatrixXd& H,
                             SensorParameters* theta) {
  const ThetaSpace& space = model.thetaSpace();
  *theta = p.theta;
  Eigen::MatrixXd Tgb = Eigen::MatrixXd::Identity(space.freeSize(), space.freeSize());
  for (size_t j = 0; j < sources.defining.size(); ++j) {
    if (!sources.defining[j]) continue;
    const FixedGainBias& fixed = space.sensors().joint_sensors[j].fixed;
    if (fixed.all()) continue;  // (a, c) never moved: the given values stand
    GainBias& gb = theta->joint_sensor[j];
    const GainBias given = gb;
    gb = forwardMap(p.inverse[j]);
    if (fixed.gain) gb = {given.gain, -p.inverse[j].c * given.gain};
    if (fixed.bias) gb.bias = given.bias;
    const int o = space.jointOffset(static_cast<int>(j));
    const int kg = space.freePosition()[o], kb = space.freePosition()[o + 1];
    const double g = gb.gain, b = gb.bias;
    if (kg >= 0) Tgb(kg, kg) = -1.0 / (g * g);
    if (kg >= 0 && kb >= 0) Tgb(kb, kg) = b / (g * g);
    if (kb >= 0) Tgb(kb, kb) = -1.0 / g;
  }
  const Eigen::MatrixXd info = Tgb.transpose() * H * Tgb;
  return uncertaintyFromInformation(model, *theta, info);
}


}  // namespace

Outcome runClassical(const MethodInput& in) {
  const Problem& problem = in.problem;
  const MeasurementModel& model = problem.model;
  const RobotModel& robot = model.robot();
  const SensorSet& sensors = model.sensors();
  const JointSources sources = findJointSources(robot, sensors);
  if (!sources.uncovered.empty())
    throw std::invalid_argument(
        "the classical regression reads every joint angle off a one-joint sensor, but no joint "
        "sensor is on: " + joinNames(sources.uncovered) +
        " (use --method stac, which also handles tendon-only joints)");
  Outcome out;
  out.fitted_frames = usableFrames(problem.obs, sources);
  out.defining_joint = sources.defining;
  const Observations used = selectFrames(problem.obs, out.fitted_frames);

  ClassicalParameters p;
  p.theta = in.seed;
  p.inverse.resize(sensors.joint_sensors.size());
  for (size_t j = 0; j < sensors.joint_sensors.size(); ++j)
    if (sources.defining[j]) p.inverse[j] = inverseMap(in.seed.joint_sensor[j]);
  fittedResidualRms(problem, in.seed,
                    neutralPose(robot).transpose().replicate(problem.obs.num_frames, 1),
                    out.before_rms);

  Regression reg(model, sources, used, problem.loss, problem.threads);
  GroupScales scales;
  NoiseModel noise = problem.seed_noise;
  const Pass first = reg.pass(p, noise, problem.seed_noise, false);
  out.initial_cost = first.cost;
  int groups = 0;  // groups with fitted readings
  for (int g = 0; g < kNumSensorGroups; ++g) groups += first.count[g] > 0;
  out.iterations =
      solveAdapting(in, sources, groups, &reg, &p, &scales, &noise, &out.converged);
  // Statistics at the final σ.
  const Pass fin = reg.pass(p, noise, problem.seed_noise, true);
  out.final_cost = fin.cost;
  for (int g = 0; g < kNumSensorGroups; ++g)
    out.after_rms[g] = fin.count[g] > 0 ? std::sqrt(fin.sse[g] / fin.count[g]) : 0.0;
  out.uncertainty = toGainBias(model, sources, p, fin.H, &out.theta);
  out.q = anglesOfEveryFrame(robot, sensors, sources, p, problem.obs);
  out.noise = noise;
  out.marker_scale = scales.kappa[0];
  return out;
}

}  // namespace stac
