// The coupled step's coordinates for a pot's map p = g q + b.
//
// Where the pot dominates what the data say of its joint's angle (a joint
// that few markers see, or see only close to its axis), every q_t follows
// its own reading, q_t = α p_t + β with α = 1/g, β = -b/g, and the only
// evidence on the map is how well the other sensors fit that motion: the
// cost, q_t profiled out, is nearly quadratic in (α, β) and far from
// quadratic in (g, b). A Gauss-Newton step in (g, b) there overshoots or
// flips the sign, is rejected, and the damped steps then crawl along the
// valley: the basin test's humanoid under partial swings (a toe swung over
// a third of its range, one marker near its axis) ended with the toe pot's
// gain at 547 against a truth of -2.03, "not converged after 200", its
// cost 0.5 above the truth's. In (α, β) the same step is nearly exact, and
// a sign is corrected through α = 0 (the joint still, g = ∞) in one step
// instead of a walk to infinity. Where the other sensors pin the angle
// (the pot only regressed on it), p is linear in (g, b) and those are the
// right coordinates. The profile of one frame, with I the information the
// other readings carry on the angle, is
//     (p - g m - b)² / (σ² + g²/I)
// (m the angle those readings alone give): quadratic in (g, b) while the
// pot's share of the angle's information, h = (g²/σ²) / (g²/σ² + I), is
// small, in (α, β) while it is large. So each free gain takes the inverse
// chart where h > 1/2, read off the reduced system as the share of the
// gain's curvature that eliminating the q_t removes.
//
// The chart turns each map about its pot's mean reading p̄: q = α (p - p̄) + β
// (β the angle at p̄). About p = 0 instead, a pot logged in encoder ticks
// about an offset (2048 ± 650 a radian) couples α and β almost
// collinearly: the damped steps then crawled (humanoid38, 3000 frames, its
// pots in ticks: 81 iterations against 4 in radians for the same answer).
// Through α = 0 the motion then mirrors about its own middle.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "stac/log.hpp"
#include "stac/theta_space.hpp"

namespace stac {

// The pots a coupled step moves in their inverse chart, and how.
class PotCharts {
 public:
  // From the reduced curvature S and the un-reduced diagonal D (both over
  // the free entries) at θ: the joint sensors whose free gain keeps less
  // than half of its curvature once the q_t are eliminated (S_gg < D_gg / 2),
  // each turned about pivots[j] (potPivots).
  PotCharts(const ThetaSpace& space, const SensorParameters& theta, const Eigen::MatrixXd& S,
            const Eigen::VectorXd& D, const std::vector<double>& pivots);
  // None: every entry in θ's own coordinates.
  explicit PotCharts(const ThetaSpace& space) : space_(&space) {}

  bool empty() const { return pots_.empty(); }
  int size() const { return static_cast<int>(pots_.size()); }

  // The system in chart coordinates: S ← Tᵀ S T, g ← Tᵀ g, T the
  // linearisation of (α, β) ↦ (g, b) for each chart pot, the identity
  // elsewhere.
  void toChart(Eigen::MatrixXd* S, Eigen::VectorXd* g) const;
  // A step in chart coordinates as the linear step T δ over the free
  // entries in θ's own coordinates (what the back-substitution takes).
  Eigen::VectorXd linearStep(const Eigen::VectorXd& chart_step) const;
  // θ moved by a step in chart coordinates: the chart pots along (α, β)
  // exactly, every other entry as ThetaSpace::plusFree.
  SensorParameters retract(const SensorParameters& theta, const Eigen::VectorXd& chart_step) const;

 private:
  struct Pot {
    int sensor = -1;           // joint sensor index
    int gain = -1, bias = -1;  // free positions (bias -1: held)
    Eigen::Matrix2d T;         // d(g, b) / d(α, β) at θ
    double pivot = 0;          // p̄
  };
  const ThetaSpace* space_;
  std::vector<Pot> pots_;
};

// Each joint sensor's mean reading over obs (0 where it has none): the
// readings its chart turns about.
std::vector<double> potPivots(const Observations& obs);

}  // namespace stac
