#include "methods/verdict.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "methods/origin_verdict.hpp"
#include "solve/q_phase.hpp"

namespace stac {
namespace {

constexpr double kRows[kNumSensorGroups] = {3.0, 1.0, 1.0};  // residual rows per reading

std::string format(const char* fmt, double a, double b = 0, double c = 0) {
  char buf[256];
  std::snprintf(buf, sizeof buf, fmt, a, b, c);
  return buf;
}

// Each group's fit against its seed σ: the fitted σ when σ was adapted, else
// the residual RMS per row (a marker's Euclidean residual has three).
void checkGroups(const MethodInput& in, const CalibrationSummary& s,
                 std::vector<std::string>* why) {
  const bool adapted = in.options.adapt_variance && in.options.method != Method::kEkf;
  for (int g = 0; g < kNumSensorGroups; ++g) {
    if (!s.group_present[g] || !(s.seed_group_sigma[g] > 0)) continue;
    const double fit = adapted ? s.group_sigma[g] : s.after_rms[g] / std::sqrt(kRows[g]);
    const double ratio = fit / s.seed_group_sigma[g];
    if (!(ratio <= kSuspectFitRatio))
      why->push_back(std::string("the ") + groupName(static_cast<SensorGroup>(g)) +
                     format(" readings fit %.3g times worse than their seed sigma (%.3g -> %.3g ",
                            ratio, s.seed_group_sigma[g], fit) +
                     groupUnit(static_cast<SensorGroup>(g)) +
                     "): a wrong minimum, a sigma in the wrong unit, or readings the model "
                     "does not explain");
  }
}

// One sensor far off its own σ while its group fits: a sensor calibrated
// into a wrong minimum (a gain sign, a folded joint). Outliers inflate an
// RMS, so only without a robust loss.
void checkSensors(const MethodInput& in, const CalibrationResult& r,
                  std::vector<std::string>* why) {
  if (in.options.loss != LossKind::kNone) return;
  const SensorSet& s = r.sensors;
  auto check = [&](const std::string& name, const ResidualStats& st, double sigma, double rows) {
    if (st.count < 10 || !(sigma > 0)) return;
    const double ratio = st.rms / (std::sqrt(rows) * sigma);
    if (!(ratio <= kSuspectSensorRatio))
      why->push_back("sensor " + name + format(" fits %.3g times worse than its sigma", ratio));
  };
  for (size_t m = 0; m < s.markers.size(); ++m)
    check(s.markers[m].name, r.marker_residual[m], s.markers[m].sigma, 3.0);
  for (size_t j = 0; j < s.joint_sensors.size(); ++j)
    if (r.joint_residual[j].rms > 0)  // a defining sensor (σ_p -> 0) has none
      check(s.joint_sensors[j].name, r.joint_residual[j], s.joint_sensors[j].sigma, 1.0);
  for (size_t j = 0; j < s.tendon_sensors.size(); ++j)
    check(s.tendon_sensors[j].name, r.tendon_residual[j], s.tendon_sensors[j].sigma, 1.0);
}

// The robot's size: the largest distance of a link origin from the base at
// the neutral pose (at least 0.1 m).
double robotSize(const RobotModel& robot) {
  KinematicsWorkspace ws(robot);
  forwardKinematics(robot, neutralPose(robot), &ws);
  double size = 0.1;
  for (const Eigen::Isometry3d& pose : ws.link_pose)
    size = std::max(size, pose.translation().norm());
  return size;
}

// A marker cannot sit farther from its link than the robot is large.
void checkMarkers(const MethodInput& in, const CalibrationResult& r,
                  std::vector<std::string>* why) {
  const SensorSet& s = r.sensors;
  if (s.markers.empty()) return;
  const double size = robotSize(in.problem.model.robot());
  for (size_t m = 0; m < s.markers.size(); ++m) {
    const double d = r.theta.marker_position[m].norm();
    if (d > size)
      why->push_back("marker " + s.markers[m].name +
                     format(" is %.3g m from its link's origin, farther than the robot is large "
                            "(%.3g m)", d, size));
  }
}

}  // namespace

std::vector<std::string> verdictOf(const MethodInput& in, const Outcome& out,
                                   const CalibrationResult& r) {
  std::vector<std::string> why;
  const CalibrationSummary& s = r.summary;
  if (in.options.method == Method::kEkf) {
    if (!s.converged) why.push_back("the filter stopped on a non-finite update");
    if (out.final_cost > out.initial_cost)
      why.push_back(format("the filter ended at a higher cost than it started (%.6g > %.6g)",
                           out.final_cost, out.initial_cost));
  } else if (!s.converged) {
    why.push_back("not converged after " + std::to_string(s.iterations) +
                  " iterations (raise --max-iterations, or check the data)");
  }
  checkGroups(in, s, &why);
  checkSensors(in, r, &why);
  checkMarkers(in, r, &why);
  checkJointOrigins(r.sensors, r.theta, &why);
  return why;
}

}  // namespace stac
