// Variance adaptation (paper §III-E): one scale κ_g per sensor group on the
// seed σ's, re-estimated from the residuals the fit leaves,
//   κ_g = sqrt((Σ w s + ν₀) / (dof_g + ν₀)),
// where s is a reading's squared residual whitened by its seed σ, w the
// robust loss's weight and dof_g the group's rows less the degrees of
// freedom the fit spent on them (the leverage of the q_t, or the
// regression's share of θ); ν₀ (the .cpp's kSeedDof) is the weight of the
// seed σ, a prior that keeps a group the q_t can fit exactly from
// collapsing. Every method that adapts σ uses this.
//
// Under a robust loss Σ w s grows with the gross errors' size (Huber's
// weight falls as 1/|r|, so w s grows as |r|: 5% of pot readings at
// 50-200 σ made the arm's pot σ 24x its truth, the pots then barely counted
// and their calibration failed). There each reading counts with the taper
// φ(s) = (1 - s/b)² below b = 4 times its χ² distribution's 99% quantile
// at the current σ, 0 beyond (smooth, so that the fixed-point iteration
// settles; readings crossing a hard bound kept σ moving), Σ φ s divided by
// the taper's share of the mean (E[φ χ²] / (k E[φ])) and dof_g over Σ φ rows.
#pragma once

#include <vector>

#include "stac/measurement.hpp"

namespace stac {

struct GroupScales {
  double kappa[kNumSensorGroups] = {1, 1, 1};
  double last_step[kNumSensorGroups] = {0, 0, 0};  // for the extrapolation
};

// Per group: Σ w s at the seed σ and the residual degrees of freedom.
struct GroupResiduals {
  double wsse[kNumSensorGroups] = {0, 0, 0};
  double dofs[kNumSensorGroups] = {0, 0, 0};
};

// The taper of a reading of `rows` rows (1-3): bound b and mean share.
struct ScaleTaper {
  double bound, mean_share;
  double weight(double s) const { return s < bound ? (1 - s / bound) * (1 - s / bound) : 0.0; }
};
ScaleTaper scaleTaper(int rows);

// Re-estimates each group's κ (a group with at most half a degree of
// freedom keeps its κ); returns the largest relative change. With
// `extrapolate`, a group whose plain updates shrink geometrically jumps to
// the series' limit (see the .cpp).
double updateScales(const GroupResiduals& residuals, bool extrapolate, GroupScales* scales);

// The seed σ's times their group's κ; joint sensors flagged in
// `unscaled_joint` (may be null) keep their seed σ.
NoiseModel scaledNoise(const NoiseModel& seed, const GroupScales& scales,
                       const std::vector<bool>* unscaled_joint = nullptr);

}  // namespace stac
