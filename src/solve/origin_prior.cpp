#include "solve/origin_prior.hpp"

#include <cmath>

namespace stac {

double originPriorCost(const ThetaSpace& space, const SensorParameters& theta) {
  double cost = 0;
  for (int i : space.freeIndex()) {
    const double s = space.priorStd(i);
    if (s > 0) cost += 0.5 * std::pow(space.value(theta, i) / s, 2);
  }
  return cost;
}

void addOriginPrior(const ThetaSpace& space, const SensorParameters& theta, Eigen::MatrixXd* S,
                    Eigen::VectorXd* g) {
  const std::vector<int>& free = space.freeIndex();
  for (size_t k = 0; k < free.size(); ++k) {
    const double s = space.priorStd(free[k]);
    if (!(s > 0)) continue;
    (*S)(k, k) += 1.0 / (s * s);
    if (g) (*g)[k] += space.value(theta, free[k]) / (s * s);
  }
}

}  // namespace stac
