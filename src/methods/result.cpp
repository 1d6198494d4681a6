// The one place that turns a method's Outcome into a CalibrationResult.
#include <algorithm>
#include <chrono>
#include <limits>


#include "methods/method.hpp"
#include "methods/mirror_ambiguity.hpp"
#include "methods/still_joints.hpp"
#include "methods/turn_ambiguity.hpp"
#include "methods/verdict.hpp"
#include "solve/pass.hpp"
#include "solve/statistics.hpp"

namespace stac {
namespace {

const char* methodName(Method m) {
  switch (m) {
    case Method::kStac: return "stac";
    case Method::kMonolithic: return "joint";
    case Method::kEkf: return "ekf";
    case Method::kClassical: return "classical";
  }
  return "";
}

// The sensors with their final σ (the marker group's κ also on mocap.sigma,
// the default of markers without their own).
SensorSet withFinalNoise(const SensorSet& sensors, const Outcome& out) {
  SensorSet s = sensors;
  for (size_t m = 0; m < s.markers.size(); ++m) s.markers[m].sigma = out.noise.marker[m];
  for (size_t j = 0; j < s.joint_sensors.size(); ++j) s.joint_sensors[j].sigma = out.noise.joint[j];
  for (size_t j = 0; j < s.tendon_sensors.size(); ++j)
    s.tendon_sensors[j].sigma = out.noise.tendon[j];
  if (!s.markers.empty()) s.mocap_sigma = sensors.mocap_sigma * out.marker_scale;
  return s;
}

// With a prior on the joint-origin corrections: per joint, the free
// components the data determines (posterior std below half the prior's)
// and those that stay on the prior.
std::vector<OriginDetermination> originDetermination(const ThetaSpace& space,
                                                     const Eigen::VectorXd& std) {
  static const char* kComponent[6] = {"x", "y", "z", "roll", "pitch", "yaw"};
  std::vector<OriginDetermination> out;
  const SensorSet& sensors = space.sensors();
  for (size_t c = 0; c < sensors.joint_origins.size(); ++c) {
    OriginDetermination d;
    d.joint = sensors.joint_origins[c].joint_name;
    for (int k = 0; k < 6; ++k) {
      const int i = space.originOffset(static_cast<int>(c)) + k;
      const double prior = space.priorStd(i);
      if (!space.free()[i] || !(prior > 0)) continue;
      (std[i] < 0.5 * prior ? d.determined : d.on_prior).push_back(kComponent[k]);
    }
    if (!d.determined.empty() || !d.on_prior.empty()) out.push_back(std::move(d));
  }
  return out;
}

// Every parameter summary.unidentifiable names gets an infinite std: a
// value the data cannot determine (a null direction of the information, a
// bias known only modulo a turn, one of two mirror configurations) is never
// returned as a confident number (SPEC §3). A mirror's gains, biases and
// markers kept their sharp local std before, and a wrong one of the two
// read as a confident answer.
void undeterminedStd(const ThetaSpace& space, const std::vector<UnidentifiableDirection>& listed,
                     Eigen::VectorXd* std) {
  if (std->size() != space.size()) return;
  for (int i = 0; i < space.size(); ++i)
    for (const UnidentifiableDirection& d : listed)
      if (std::find(d.parameters.begin(), d.parameters.end(), space.names()[i]) !=
          d.parameters.end())
        (*std)[i] = std::numeric_limits<double>::infinity();
}

}  // namespace

CalibrationResult makeResult(const MethodInput& in, Outcome&& out, RowMatrix* joint_angles) {
  const Problem& problem = in.problem;
  const MeasurementModel& model = problem.model;
  CalibrationResult result;
  result.sensors = withFinalNoise(model.sensors(), out);
  nearestTurnForContinuousJoints(model, &out.theta, &out.q);
  result.theta = out.theta;
  // Statistics over the frames the method fitted.
  const bool all = out.fitted_frames.empty();
  const Observations subset = all ? Observations() : selectFrames(problem.obs, out.fitted_frames);
  const Observations& fitted = all ? problem.obs : subset;
  RowMatrix fitted_q;
  if (!all) {
    fitted_q.resize(static_cast<Eigen::Index>(out.fitted_frames.size()), model.dof());
    for (size_t k = 0; k < out.fitted_frames.size(); ++k)
      fitted_q.row(k) = out.q.row(out.fitted_frames[k]);
  }
  const RowMatrix& q = all ? out.q : fitted_q;
  residualStatistics(model, result.theta, fitted, q, problem.threads, &result);

  CalibrationSummary& summary = result.summary;
  summary.method = methodName(in.options.method);
  if (in.options.method == Method::kStac) summary.q_phase = qPhaseName(in.options.stac.q_phase);
  summary.iterations = out.iterations;
  summary.converged = out.converged;
  summary.initial_cost = out.initial_cost;
  summary.final_cost = out.final_cost;
  summary.frames = fitted.num_frames;
  std::copy(out.before_rms, out.before_rms + kNumSensorGroups, summary.before_rms);
  std::copy(out.after_rms, out.after_rms + kNumSensorGroups, summary.after_rms);
  summary.unidentifiable = std::move(out.uncertainty.unidentifiable);
  for (UnidentifiableDirection& d : turnAmbiguities(model, result.theta, out.q))
    summary.unidentifiable.push_back(std::move(d));
  for (UnidentifiableDirection& d : stillJoints(model, fitted, problem.seed_noise, out.noise))
    summary.unidentifiable.push_back(std::move(d));
  // Where the run found the mirrors' candidates at its end, they are
  // listed from there: the whole turns that nearestTurnForContinuousJoints
  // moved θ and q by move both alike, and the listing compares the two.
  for (UnidentifiableDirection& d :
       all && out.mirrors
           ? mirrorListing(model.thetaSpace(), *out.mirrors, out.uncertainty.std)
           : mirrorAmbiguities(problem, fitted, result.theta, out.noise, q, out.uncertainty.std))
    summary.unidentifiable.push_back(std::move(d));
  Eigen::VectorXd std = out.uncertainty.std;
  undeterminedStd(model.thetaSpace(), summary.unidentifiable, &std);
  result.std = model.thetaSpace().toParameterStd(std);
  if (out.uncertainty.std.size() == model.thetaSpace().size())
    summary.origins = originDetermination(model.thetaSpace(), out.uncertainty.std);
  summary.downweighted = downweightedReadings(problem.on(fitted), result.theta, out.noise, q,
                                              in.options.max_downweighted);
  const std::vector<bool>* defining = out.defining_joint.empty() ? nullptr : &out.defining_joint;
  CalibrationSummary seed;
  summariseGroupNoise(model.sensors(), problem.seed_noise, &seed, defining);
  std::copy(seed.group_sigma, seed.group_sigma + kNumSensorGroups, summary.seed_group_sigma);
  summariseGroupNoise(model.sensors(), out.noise, &summary, defining);
  summary.verdict = verdictOf(in, out, Fit{fitted, q}, result);
  summary.wall_time = std::chrono::duration<double>(Clock::now() - in.start).count();
  if (joint_angles) *joint_angles = std::move(out.q);
  return result;
}

}  // namespace stac
