// The human summary of a calibration (what stac_calib prints).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "stac/calibrate.hpp"
#include "stac/theta_space.hpp"

namespace stac {
namespace {


struct ParameterChange {
  std::string name;
  double before = 0, after = 0;
  double score = 0;  // |after - before| in the parameter's typical units
};

// The n free parameters whose values changed most between two θ.
std::vector<ParameterChange> largestChanges(const ThetaSpace& space,
                                            const SensorParameters& before,
                                            const SensorParameters& after, int n) {
  const Eigen::VectorXd scale = space.scale(after);
  const Eigen::VectorXd change = space.minus(after, before);
  std::vector<ParameterChange> all;
  bool rotation_listed = false;
  for (int i : space.freeIndex()) {
    const ThetaEntry e = space.entry(i);
    if (e.block == ThetaBlock::kMocapRotation) {
      // One entry for the turn: its components depend on the axes chosen.
      if (rotation_listed) continue;
      rotation_listed = true;
      const double angle = change.segment<3>(ThetaSpace::kRotationOffset).norm();
      all.push_back({"mocap.frame.rotation (angle)", 0.0, angle, angle});
      continue;
    }
    all.push_back({space.names()[i], space.value(before, i), space.value(after, i),
                   std::abs(change[i]) / scale[i]});
  }
  std::stable_sort(all.begin(), all.end(),
                   [](const ParameterChange& a, const ParameterChange& b) { return a.score > b.score; });
  if (static_cast<int>(all.size()) > n) all.resize(n);
  return all;
}

// The summary's unidentifiable directions and down-weighted readings.
std::string diagnostics(const CalibrationSummary& s) {
  std::ostringstream o;
  char buf[256];
  o << "\nunidentifiable: ";
  if (s.unidentifiable.empty()) {
    o << "none\n";
  } else {
    o << s.unidentifiable.size() << " direction(s) the data cannot determine (fix one of the "
      << "parameters with `fixed`, e.g. `fixed: [bias]` on a joint sensor, or add markers):\n";
    for (const UnidentifiableDirection& d : s.unidentifiable) {
      o << "  - " << d.reason << "\n    parameters:";
      for (const std::string& p : d.parameters) o << " " << p;
      o << "\n";
    }
  }
  const int* spikes = s.spikes_set_aside;
  if (spikes[0] + spikes[1] + spikes[2] > 0)
    o << "\nreadings set aside before the fit as spikes in time: " << spikes[0] << " marker, "
      << spikes[1] << " joint, " << spikes[2] << " tendon\n";
  if (!s.downweighted.empty()) {
    o << "\nreadings the robust loss down-weighted most (frame, sensor, weight):\n";
    for (const DownweightedReading& d : s.downweighted) {
      std::snprintf(buf, sizeof buf, "  %8d  %-24s %.3g\n", d.frame, d.sensor.c_str(), d.weight);
      o << buf;
    }
  }
  return o.str();
}

}  // namespace

std::string briefReport(const RobotModel& robot, const SensorParameters& seed,
                        const CalibrationResult& r) {
  const SensorSet& sensors = r.sensors;
  const CalibrationSummary& s = r.summary;
  std::ostringstream o;
  char buf[256];
  o << "Calibration of " << (robot.name().empty() ? "robot" : robot.name()) << ": "
    << s.frames << " frames, " << robot.dof() << " joints, " << sensors.markers.size()
    << " markers, " << sensors.joint_sensors.size() << " joint sensors, "
    << sensors.tendon_sensors.size() << " tendon sensors\n";
  const std::string steps = s.method == "ekf" ? "one forward pass over the frames"
                            : std::to_string(s.iterations) +
                                  (s.iterations == 1 ? " iteration" : " iterations");
  std::snprintf(buf, sizeof buf, "method %s%s%s, %s, %s, %.2f s\n", s.method.c_str(),
                s.q_phase.empty() ? "" : " / q-phase ", s.q_phase.c_str(), steps.c_str(),
                s.converged ? "converged" : "NOT converged (iteration limit)", s.wall_time);
  o << buf;
  o << "\nresidual RMS per group      before        after        sigma\n";
  for (int g = 0; g < kNumSensorGroups; ++g) {
    if (!s.group_present[g]) continue;
    std::snprintf(buf, sizeof buf, "  %-8s (%-3s)       %12.6g %12.6g %12.6g\n",
                  groupName(static_cast<SensorGroup>(g)), groupUnit(static_cast<SensorGroup>(g)), s.before_rms[g],
                  s.after_rms[g], s.group_sigma[g]);
    o << buf;
  }
  // Parameters that moved most, in their own typical units.
  const std::vector<ParameterChange> moved = largestChanges(ThetaSpace(sensors), seed, r.theta, 8);
  if (!moved.empty()) {
    o << "\nparameters that moved most           seed          final\n";
    for (const ParameterChange& c : moved) {
      std::snprintf(buf, sizeof buf, "  %-32s %12.6g %14.6g\n", c.name.c_str(), c.before, c.after);
      o << buf;
    }
  }
  o << diagnostics(s);
  if (s.verdict.empty()) {
    o << "\nverdict: ok\n";
  } else {
    o << "\nverdict: SUSPECT, the result failed " << s.verdict.size() << " of its own checks:\n";
    for (const std::string& reason : s.verdict) o << "  - " << reason << "\n";
  }
  return o.str();
}


}  // namespace stac
