// Uncertainty and identifiability of θ with every q_t marginalised out.
//
// The Gauss-Newton information matrix of (q_1..q_T, θ) is block-arrowhead;
// its Schur complement onto θ, S = H_θθ - Σ_t H_θq H_qq⁻¹ H_qθ, is the
// information about θ alone. Eigen-directions of S (parameters scaled to
// comparable units) with (near) zero information are directions the data
// cannot determine: they are reported by name, and every parameter taking
// part in one gets an infinite standard deviation. The others get
// sqrt(diag(S⁺)), or where each frame's θ score g̃_t is known the larger of
// that and the sandwich sqrt(diag(S⁺ B S⁺)), B = Σ_t g̃_t g̃_tᵀ. S⁺ alone
// trusts the noise model; the sandwich does not: under a robust loss the
// IRLS weights make S⁺ too small, and where readings of one frame share an
// error (the virtual points of one tracked rigid body, fitted as markers)
// only the frames' scores show it. With few frames B is noisy and of rank at
// most their count, so it may widen a std but never narrow one.
#pragma once

#include <Eigen/Core>
#include <limits>
#include <vector>

#include "stac/calibration.hpp"
#include "stac/log.hpp"
#include "stac/measurement.hpp"

namespace stac {

struct UncertaintyResult {
  Eigen::VectorXd std;            // per θ entry (MeasurementModel layout)
  Eigen::MatrixXd information;    // S, free entries only (rows = free index)
  std::vector<int> free_index;    // θ index of each row of `information`
  std::vector<UnidentifiableDirection> unidentifiable;
  // How much the cost could still fall from here: the Gauss-Newton
  // decrement ½ gᵀ H⁺ g of (q_1..q_T, θ), θ's part over the directions the
  // data determine (an undetermined one is as flat as its gradient is
  // small, and a step along it changes nothing the result claims). A
  // displacement of k std along the information's ellipsoid costs k²/2, so
  // a decrement d puts the optimum within sqrt(2 d) std of θ. NaN where
  // not computed (no gradient given, or nothing free).
  double decrement = std::numeric_limits<double>::quiet_NaN();
};

UncertaintyResult estimateUncertainty(const MeasurementModel& model,
                                      const SensorParameters& theta,
                                      const NoiseModel& noise, const RobustLoss& loss,
                                      const Observations& obs, const RowMatrix& q,
                                      int threads, std::vector<FrameWorkspace>* ws);

// The same analysis for an information matrix S about θ computed elsewhere
// (free entries only, in MeasurementModel order: e.g. the Gauss-Newton JᵀJ
// of a regression over θ alone, or the inverse of a filter's covariance).
// With `gradient` (the reduced gradient over the free entries), also the
// decrement, q_decrement being the q_t's own part.
UncertaintyResult uncertaintyFromInformation(const MeasurementModel& model,
                                             const SensorParameters& theta,
                                             const Eigen::MatrixXd& S,
                                             const Eigen::MatrixXd* score_outer = nullptr,
                                             const Eigen::VectorXd* gradient = nullptr,
                                             double q_decrement = 0.0);

}  // namespace stac
