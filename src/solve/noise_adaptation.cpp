#include "solve/noise_adaptation.hpp"

#include <algorithm>
#include <cmath>

namespace stac {
namespace {

// The seed σ counts as this many residual degrees of freedom of its group
// (an inverse-gamma prior on σ² with its mode at the seed): negligible
// beside a long log's, decisive where a group has none left. Without it
// a group that the q_t can fit exactly (one marker and a redundant arm,
// several virtual points of one tracked rigid body) has no residual and no
// residual dof, the estimate is 0/0, and the fixed-point iteration drifts
// towards σ = 0 over hundreds of iterations, the group then absorbing the
// fit of the others (seen on a real TIAGo recording).
constexpr double kSeedDof = 20.0;

}  // namespace

ScaleTaper scaleTaper(int rows) {
  // b = 4 τ99(χ²_k); E[φ χ²_k] / (k E[φ]) by quadrature.
  static constexpr ScaleTaper kTapers[] = {
      {26.539588, 0.856086}, {36.841360, 0.892140}, {45.379468, 0.910368}};
  return kTapers[std::clamp(rows, 1, 3) - 1];
}

double updateScales(const GroupResiduals& residuals, bool extrapolate, GroupScales* scales) {
  double change = 0;
  for (int g = 0; g < kNumSensorGroups; ++g) {
    const double dofs = residuals.dofs[g];
    if (dofs <= 0.5) continue;
    double& kappa = scales->kappa[g];
    double& last = scales->last_step[g];
    const double k = std::max(std::sqrt((residuals.wsse[g] + kSeedDof) / (dofs + kSeedDof)), 1e-9);
    const double step = k - kappa;
    const double ratio = last != 0 ? step / last : 0;
    double next = k;
    // The re-estimate is a fixed-point iteration (the fit, and so the
    // residuals and the dof the q_t took, follow σ) that contracts slowly,
    // by about half per iteration when pots carry most of their joints'
    // information: when two plain updates of a group shrink geometrically,
    // jump to the limit of that geometric series (Aitken's Δ²), then take a
    // plain update again. Only on clear trends (small steps mix in the fit's
    // own settling), and never far from the plain estimate: far from the
    // optimum the "trend" may be the fit changing basin, not σ converging.
    if (extrapolate && ratio > 0 && ratio < 0.9 && std::abs(step) > 1e-3 * kappa) {
      next = std::clamp(kappa + step / (1 - std::min(ratio, 0.6)), 0.8 * k, 1.25 * k);
      last = 0;
    } else {
      last = step;
    }
    change = std::max(change, std::abs(next - kappa) / kappa);
    kappa = next;
  }
  return change;
}

NoiseModel scaledNoise(const NoiseModel& seed, const GroupScales& scales,
                       const std::vector<bool>* unscaled_joint) {
  NoiseModel noise = seed;
  for (double& s : noise.marker) s *= scales.kappa[0];
  for (size_t j = 0; j < noise.joint.size(); ++j)
    if (!unscaled_joint || !(*unscaled_joint)[j]) noise.joint[j] *= scales.kappa[1];
  for (double& s : noise.tendon) s *= scales.kappa[2];
  return noise;
}

}  // namespace stac
