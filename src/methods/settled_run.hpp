// Whether a run the iteration limit stopped has nonetheless converged.
//
// The alternation stops when the cost decreases by less than
// options.tolerance per iteration and σ has settled. Along a direction the
// data barely determine (the bundled hand's thumb, its pots and tendons
// trading off about one axis, on partial swings) the parameters can keep
// creeping, and the cost and σ moving by a little more than that, for
// hundreds of iterations, at a point from which the cost can no longer
// fall by anything that matters: a right calibration then reported "not
// converged" at the limit, a false alarm. So at the limit the run is asked
// what a Gauss-Newton step could still gain (UncertaintyResult::decrement,
// at the final σ): a displacement of k std costs k²/2, so a decrement below
// kSettledStd²/2 puts the optimum within kSettledStd std of the result, and
// with σ's last step below kSettledScale (relative) the run has settled:
// converged.
#pragma once

namespace stac {

// The distance to the optimum, in std along the information's ellipsoid,
// below which a run has settled: it adds at most 5% to the result's error
// (sqrt(1 + 0.3²)), immaterial beside its std. (The bundled hand on partial
// swings, fresh truth 15 of seed 7, crawled along its thumb's trade-off with
// its optimum 0.28 std away, the cost oscillating by 1e-5 of itself as σ
// followed: right, and flagged "not converged".)
constexpr double kSettledStd = 0.3;
// σ's last relative step below which it has settled (as the iteration's
// own criterion).
constexpr double kSettledScale = 1e-3;

// Whether a run whose Gauss-Newton decrement at its end is `decrement` and
// whose σ scales last changed by `scale_change` (relative) has settled.
bool settled(double decrement, double scale_change);

}  // namespace stac
