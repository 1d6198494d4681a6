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

#include <string>
#include <utility>
#include <vector>

#include "solve/problem.hpp"
#include "stac/calibration.hpp"
#include "stac/theta_space.hpp"

namespace stac {

class WideBasin;
struct Estimate;

// The configurations that fit as well as an estimate (each the reason it
// is listed and its refined θ) and the estimate's own θ refined on the
// same subsample (WideBasin::equivalentMoves), before the std says which
// parameters each moves: found once, at the run's end (alternation.cpp
// takeBetterEquivalent), and listed by the result.
struct MirrorCandidates {
  SensorParameters refitted;
  std::vector<std::pair<std::string, SensorParameters>> moves;
};

// Whether mirrors are looked for at all: pots to mirror, and angles in
// every frame.
bool mirrorsApply(const MeasurementModel& model, const RowMatrix& q);

// The candidates from est that `basin` finds; with `better` (if given) the
// one that fits better than est (WideBasin::jumpToBetterEquivalent) applied
// to *better on basin's whole log; then the candidates are those of est.
MirrorCandidates mirrorCandidates(const WideBasin& basin, const Estimate& est,
                                  Estimate* better = nullptr, bool* moved = nullptr);

// One entry per candidate that moves some parameter by more than 3 of its
// std (`std`: theta's, indexed by ThetaSpace), listing every parameter it
// so moves.
std::vector<UnidentifiableDirection> mirrorListing(const ThetaSpace& space,
                                                   const MirrorCandidates& candidates,
                                                   const Eigen::VectorXd& std);

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
