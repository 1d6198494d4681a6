// Variance adaptation (paper §III-E): one scale κ_g per sensor group on the
// seed σ's, re-estimated from the residuals the fit leaves,
//   κ_g = sqrt((Σ w s + ν₀) / (dof_g + ν₀)),
// where s is a reading's squared residual whitened by its seed σ, w the
// robust loss's weight and dof_g the group's rows less the degrees of
// freedom the fit spent on them (the leverage of the q_t, or the
// regression's share of θ); ν₀ (the .cpp's kSeedDof) is the weight of the
// seed σ, a prior that keeps a group the q_t can fit exactly from
// collapsing. Every method that adapts σ uses this.
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
