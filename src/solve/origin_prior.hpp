// The Gaussian prior (MAP) on the joint-origin corrections (SPEC §3
// `prior_std`): ½ Σ (c_i / σ_i)² over every free component that has one.
// Every solver that forms the θ-side normal equations adds it here, so the
// alternation, the coupled steps, the uncertainty and the monolithic problem
// optimise and report the same posterior.
#pragma once

#include <Eigen/Core>

#include "stac/theta_space.hpp"

namespace stac {

// ½ Σ (value / prior std)² over the free entries with a prior.
double originPriorCost(const ThetaSpace& space, const SensorParameters& theta);

// Adds the prior's curvature (1/σ² on the diagonal) to S and, when g is
// given, its gradient (value/σ²) to g; both over the free entries.
void addOriginPrior(const ThetaSpace& space, const SensorParameters& theta, Eigen::MatrixXd* S,
                    Eigen::VectorXd* g);

}  // namespace stac
