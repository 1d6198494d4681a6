#include "methods/settled_run.hpp"

#include <algorithm>
#include <cmath>

namespace stac {

void IterationTrail::push(const SensorParameters& t, const GroupScales& s) {
  if (static_cast<int>(theta.size()) == kTrailLength) {
    theta.erase(theta.begin());
    scales.erase(scales.begin());
  }
  theta.push_back(t);
  scales.push_back(s);
}

namespace {

// The tail Σ_{k≥1} ρ^k |last| of steps shrinking at least by ρ, the larger
// of the two ratios of the three step sizes (oldest first); ∞ where they do
// not shrink and the last is not zero. Two ratios, not one: a single ratio
// of two steps can be small by chance where the steps are not geometric.
double geometricTail(double s0, double s1, double s2) {
  if (s2 == 0) return 0.0;
  if (!(s1 > s2) || !(s0 > s1)) return INFINITY;
  const double rho = std::max(s2 / s1, s1 / s0);
  return s2 * rho / (1 - rho);
}

}  // namespace

bool settledWithinStd(const ThetaSpace& space, const IterationTrail& trail,
                      const Eigen::VectorXd& std) {
  if (static_cast<int>(trail.theta.size()) < kTrailLength) return false;
  // Steps in std units over the determined free entries: their norms give
  // the rate (one for all: a single entry's steps may be rounding), the
  // largest entry the size.
  double norm[3] = {0, 0, 0}, last_max = 0;
  for (int k = 0; k < 3; ++k) {
    const Eigen::VectorXd step = space.minus(trail.theta[k + 1], trail.theta[k]);
    for (int i : space.freeIndex()) {
      if (!(std[i] > 0) || !std::isfinite(std[i])) continue;  // undetermined: passes
      const double z = std::abs(step[i]) / std[i];
      norm[k] += z * z;
      if (k == 2) last_max = std::max(last_max, z);
    }
  }
  for (double& n : norm) n = std::sqrt(n);
  if (last_max > 0 &&
      !(geometricTail(norm[0], norm[1], norm[2]) / norm[2] * last_max <= kSettledStd))
    return false;
  for (int g = 0; g < kNumSensorGroups; ++g) {
    double step[3];
    for (int k = 0; k < 3; ++k)
      step[k] = std::abs(trail.scales[k + 1].kappa[g] - trail.scales[k].kappa[g]);
    if (!(geometricTail(step[0], step[1], step[2]) <= kSettledScale * trail.scales[3].kappa[g]))
      return false;
  }
  return true;
}

}  // namespace stac
