// The one Levenberg-Marquardt damping policy (after Ceres's
// trust_region_strategy): every solver of STAC — the per-frame q-phase, the
// coupled (q, θ) steps, the classical regression — damps its normal
// equations H the same way and moves λ by the same rule:
//   (H + λ diag(H) + ε I) δ = -g,   ε = 1e-12 max(1, max diag H)
// diag(H) keeps the step invariant to each parameter's unit; ε keeps a
// parameter that no reading sees at its value. λ falls after an accepted
// step and rises after a rejected one, within bounds.
//
// The coupled steps' reduced system over θ mixes units far more (a pot's
// inverse chart in encoder ticks beside angles and metres) and takes a
// ridge relative to each entry's own curvature instead (addScaleFreeDamping):
//   E = diag(e_i),   e_i = 1e-12 H_ii where H_ii > 1e-12 ε, else ε,
// so that the step there is invariant to each parameter's unit too; ε
// still keeps a parameter no reading sees, or only rounding does (24 orders
// below the largest), at its value. (ε on every entry damped a parameter of
// small curvature in its own unit far more than the rest: humanoid38, 3000
// frames, its pots logged in encoder ticks, the gains' curvature 12 orders
// below the charts' largest, took 11 iterations against 4 in radians for
// the same answer.) Not in the other solvers: their systems are one
// frame's angles, or the initialisation's short scoring fits, whose
// choices among starts were tuned with ε (with the relative ridge there
// too, ur5's plain-log basin truth 10 started, and ended, in a wrong
// minimum).
//
// The three users differ only in how boldly λ moves (LmSchedule): a frame's
// 1..38 joint angles are cheap to retry, a coupled step over every frame is
// not, so its λ grows faster and stays within a narrower range.
#pragma once

#include <Eigen/Core>
#include <algorithm>

namespace stac {

struct LmSchedule {
  double shrink = 3.0;   // λ /= shrink after an accepted step
  double grow = 4.0;     // λ *= grow after a rejected one
  double min = 1e-10;
  double max = 1e12;
};

// The schedules in use, in one place.
constexpr LmSchedule kFrameSchedule{3.0, 4.0, 1e-10, 1e12};       // q-phase, per frame
constexpr LmSchedule kCoupledSchedule{3.0, 8.0, 1e-9, 1e8};       // coupled (q, θ) steps
constexpr LmSchedule kRegressionSchedule{3.0, 4.0, 1e-12, 1e12};  // classical regression

inline double acceptedStep(const LmSchedule& s, double lambda) {
  return std::max(lambda / s.shrink, s.min);
}
inline double rejectedStep(const LmSchedule& s, double lambda) {
  return std::min(lambda * s.grow, s.max);
}

// The ridge ε of a system whose diagonal is `diagonal`.
inline double ridge(const Eigen::Ref<const Eigen::VectorXd>& diagonal) {
  return 1e-12 * std::max(1.0, diagonal.size() ? diagonal.maxCoeff() : 0.0);
}

// The ridge of an entry whose diagonal is d (ε = ridge of the system):
// relative where a reading sees it.
inline double ridgeOf(double d, double eps) { return d > 1e-12 * eps ? 1e-12 * d : eps; }

// A += λ diag(D) + ε I; A and D square and of one size (usually A = H = D,
// or A a copy of H).
template <typename MatrixA, typename MatrixD>
void addDamping(double lambda, const MatrixD& D, MatrixA* A) {
  const double eps = ridge(D.diagonal());
  for (Eigen::Index i = 0; i < A->rows(); ++i) (*A)(i, i) += lambda * D(i, i) + eps;
}

// A += λ diag(D) + E (above): the coupled steps' reduced system.
template <typename MatrixA, typename MatrixD>
void addScaleFreeDamping(double lambda, const MatrixD& D, MatrixA* A) {
  const double eps = ridge(D.diagonal());
  for (Eigen::Index i = 0; i < A->rows(); ++i)
    (*A)(i, i) += lambda * D(i, i) + ridgeOf(D(i, i), eps);
}

}  // namespace stac
