// Pots on joints the log does not move (see still_joints.hpp).
#include "methods/still_joints.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdio>
#include <string>

namespace stac {

std::vector<UnidentifiableDirection> stillJoints(const MeasurementModel& model,
                                                 const Observations& obs,
                                                 const NoiseModel& seed_noise,
                                                 const NoiseModel& fitted_noise) {
  const SensorSet& sensors = model.sensors();
  assert(fitted_noise.joint.empty() ||
         fitted_noise.joint.size() == sensors.joint_sensors.size());
  std::vector<UnidentifiableDirection> out;
  for (size_t s = 0; s < sensors.joint_sensors.size(); ++s) {
    const JointSensorConfig& sc = sensors.joint_sensors[s];
    const double fitted = fitted_noise.joint.empty() ? 0.0 : fitted_noise.joint[s];
    const double sigma =
        std::max(seed_noise.joint[s], std::min(fitted, kStillFittedCap * seed_noise.joint[s]));
    if (sc.fixed.any() || !(sigma > 0) || obs.joint.cols() <= static_cast<Eigen::Index>(s))
      continue;
    // Two passes over the readings present (one pass loses the variance
    // of raw counts with a large offset).
    const Eigen::ArrayXd p = obs.joint.col(static_cast<Eigen::Index>(s)).array();
    const auto present = p.isFinite();
    const Eigen::Index n = present.count();
    if (n < 2) continue;
    const double mean = present.select(p, 0.0).sum() / n;
    const double variance = present.select((p - mean).square(), 0.0).sum() / n;
    const double sampling = 3 * std::sqrt(2.0 / static_cast<double>(n));
    const double bound = std::max(kStillSpread * kStillSpread, 1 + sampling);
    if (variance > bound * sigma * sigma) continue;
    const double spread = std::sqrt(variance);
    char buf[200];
    std::snprintf(buf, sizeof buf, "%.3g against a sigma of %.3g", spread, sigma);
    const std::string joint = model.robot().movableJoints()[sc.joint].name;
    out.push_back({{"joint_sensors." + sc.name + ".gain", "joint_sensors." + sc.name + ".bias"},
                   sc.name + "'s readings vary by no more than their noise (std " + buf +
                       "): the log does not move joint " + joint + ", so its gain, and its " +
                       "bias with it, are not in the data; log a motion of " + joint,
                   Undetermined::kStillJoint});
  }
  return out;
}

}  // namespace stac
