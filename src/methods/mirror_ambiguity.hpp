// Configurations of the joints the data cannot tell apart (internal).
//
// Some serial chains pass through the same places with a joint mirrored and
// the joints next to it half a turn away (the Panda's q1+π, −q2, q3+π; a
// spherical wrist's flip). Where the markers on the links in between are
// free to move with them and the log's motion fits within the limits
// either way, both configurations fit the data exactly alike, each a sharp
// minimum: the local std cannot show it, and the pots' gains and biases
// (and the markers in between) have two equally good values. Such jumps
// (minimumMoves) are listed among the parameters the data cannot
// determine, which makeResult then gives no std.
#pragma once

#include <vector>

#include "solve/problem.hpp"
#include "stac/calibration.hpp"

namespace stac {

// One entry per jump from (theta, q) that fits `obs` as well
// (WideBasin::equivalentMoves) and moves some parameter by more than 3 of
// its std (`std`: theta's, indexed by ThetaSpace), listing every parameter
// it so moves; `noise` the calibrated σ.
std::vector<UnidentifiableDirection> mirrorAmbiguities(const Problem& problem,
                                                       const Observations& obs,
                                                       const SensorParameters& theta,
                                                       const NoiseModel& noise, const RowMatrix& q,
                                                       const Eigen::VectorXd& std);

}  // namespace stac
