// Whether a run the iteration limit stopped has nonetheless settled.
//
// The alternation stops when the cost decreases by less than
// options.tolerance per iteration and σ has settled. Along a direction the
// data barely determine (the bundled hand's thumb, its pots and tendons
// trading off about one axis, on partial swings) the cost and σ can keep
// moving by a little more than that for hundreds of iterations while every
// parameter the data determine has long stopped: a right calibration then
// reported "not converged" at the limit, a false alarm. So at the limit the
// last iterations' θ steps are measured in units of the final std: where
// they shrink geometrically and the distance left to their limit (the
// geometric series' tail) is below kSettledStd of every parameter's std
// (undetermined ones, std ∞, pass), and σ's steps likewise shrink to a
// negligible tail, the run has settled: converged.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "solve/noise_adaptation.hpp"
#include "stac/calibration.hpp"
#include "stac/theta_space.hpp"

namespace stac {

// The tail of a run's iterations: θ and the σ scales after each of the last
// (at most) kTrailLength, oldest first.
constexpr int kTrailLength = 4;
struct IterationTrail {
  std::vector<SensorParameters> theta;
  std::vector<GroupScales> scales;
  void push(const SensorParameters& t, const GroupScales& s);
};

// What is left to go, as a share of std, below which a parameter has settled.
constexpr double kSettledStd = 0.1;
// The same for σ's scales, relative.
constexpr double kSettledScale = 1e-3;

// Whether the trail's last three steps shrink and their geometric tail is
// below kSettledStd of `std` (per θ entry, the final uncertainty's) for
// every free parameter with a finite std, and below kSettledScale (relative)
// for every σ scale. False on a shorter trail.
bool settledWithinStd(const ThetaSpace& space, const IterationTrail& trail,
                      const Eigen::VectorXd& std);

}  // namespace stac
