#include "methods/redescending_check.hpp"

#include <cmath>
#include <cstdio>

namespace stac {

double largestShiftInStd(const ThetaSpace& space, const SensorParameters& a,
                         const SensorParameters& b, const Eigen::VectorXd& std, int* which) {
  const Eigen::VectorXd d = space.minus(a, b);
  double largest = 0;
  *which = -1;
  for (int i : space.freeIndex()) {
    if (!(std[i] > 0) || !std::isfinite(std[i])) continue;
    const double z = std::abs(d[i]) / std[i];
    if (z > largest) largest = z, *which = i;
  }
  return largest;
}

std::string lossDisagreement(const MeasurementModel& model, const Outcome& huber,
                             const SensorParameters& cauchy) {
  const ThetaSpace& space = model.thetaSpace();
  int which = -1;
  const double z = largestShiftInStd(space, huber.theta, cauchy, huber.uncertainty.std, &which);
  if (z <= kLossShiftStd) return {};
  char buf[96];
  std::snprintf(buf, sizeof buf, "%.3g", z);
  return "Huber's loss and the redescending Cauchy loss (same seed, same scale) disagree by " +
         std::string(buf) + " std on the " + space.ownerPhrase(which) +
         ": gross readings bias Huber's fit here (a gross reading from the sensor that "
         "dominates its joint drags the frame's angle along); rerun with --loss cauchy";
}

}  // namespace stac
