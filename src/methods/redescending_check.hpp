// Huber's loss bounds a gross reading's pull but never lets go of it: where
// the reading's sensor dominates its joint in a frame (a pot on a finger
// whose markers dropped out), the frame's angle follows the gross reading
// all the way, the weaker readings of that frame (the tendons spanning the
// joint) are the ones left misfitting, and setting aside the readings
// beyond the σ taper's bound then removes the good ones. The θ that comes
// out is biased by several of its std, and the frames' angles are a
// consistent, wrong local minimum that no redescending finish from there
// leaves (measured on the basin test's hand24 with 5% gross readings and
// 30% dropout: 1 of 20 truths reached under Huber, 8 silent misses; 16 of 20
// with Cauchy's loss from the same seed, error RMS 1.05 std).
// So a Huber run that found gross readings is checked against a run with
// Cauchy's redescending loss from the same seed; if Cauchy's passes every
// check of its own (a non-convex loss may also end in a wrong minimum,
// which says nothing of Huber's) and the two disagree beyond kLossShiftStd
// of Huber's reported std, the verdict says so and names the remedy (--loss
// cauchy).
#pragma once

#include <string>
#include <vector>

#include "methods/method.hpp"

namespace stac {

// Huber's and Cauchy's estimates further apart than this many of Huber's
// std in some parameter disagree. Two right fits of the same readings
// differ only through the readings they weigh differently: 0.4-2.6 std at
// most over the basin test's arm4, gimbal2 and ur5 truths with 5% gross
// readings, where Huber's fit reached the truth. A Huber fit 4.3 std off on
// the hand was 3.9 std from Cauchy's, so 4 (the basin test's "reached")
// would let it pass.
constexpr double kLossShiftStd = 3.0;

// The largest |a - b| over the free θ entries, in units of std (entries
// with a zero or infinite std skipped; an entry with a positive `period`
// compared modulo it); *which: that entry's index.
double largestShiftInStd(const ThetaSpace& space, const SensorParameters& a,
                         const SensorParameters& b, const Eigen::VectorXd& std, int* which,
                         const Eigen::VectorXd* period = nullptr);

// What the check needs of the Cauchy run's result.
struct CauchyFit {
  SensorParameters theta;
  Eigen::VectorXd std;  // per θ entry, as Outcome::uncertainty.std
  std::vector<UnidentifiableDirection> unidentifiable;
  RowMatrix q;          // its joint angles (a start for Huber's run)
};

// The largest shift between Huber's and Cauchy's θ in units of `std` (per
// θ entry), a bias Cauchy's result knows only modulo a turn compared modulo
// that turn; with skip_listed, any other parameter it lists undetermined
// not compared (the verdict's comparison; the restart from Cauchy's end
// compares them). *which: that entry's index (-1: none). 0 where std does
// not cover θ.
double shiftInStd(const MeasurementModel& model, const Outcome& huber, const CauchyFit& cauchy,
                  const Eigen::VectorXd& std, int* which, bool skip_listed);

// The verdict reason when `huber`'s θ is more than kLossShiftStd from
// `cauchy`'s (empty: they agree), each entry measured in the larger of the
// two fits' std: where Cauchy's weights leave a parameter weakly determined
// or undetermined (a finger whose pot's stroke is its noise: std +inf under
// Cauchy), Cauchy's value of it contradicts nothing. A bias that Cauchy's
// result lists as known only modulo a turn is compared modulo that turn.
std::string lossDisagreement(const MeasurementModel& model, const Outcome& huber,
                             const CauchyFit& cauchy);

// The check itself, for runStac's Huber run `in` that set gross readings
// aside and ended in `huber`: the whole run again from the same seed with
// Cauchy's loss at the same scale (its progress reported as stage
// "check"), then reconcileWithCauchy() if Cauchy's result passes its own
// checks; else `huber`.
Outcome crossCheckWithCauchy(const MethodInput& in, Outcome huber);

// Huber's end against Cauchy's. Where they differ beyond kLossShiftStd of
// either's std, Huber's run goes on once more from Cauchy's end, and that
// run replaces `huber` if it converged and fits every reading better
// under Cauchy's loss at `huber`'s σ, the q_t solved for (the first run had
// ended in a wrong minimum). Where they still disagree, Cauchy's run goes
// on from Huber's end: if it stays with it and fits Cauchy's problem as
// well as Cauchy's own end, the disagreement was Cauchy's run's (its end
// off the minimum), not Huber's bias. The outcome returned has
// loss_disagreement set (verdict reason) where it and Cauchy's still
// disagree.
Outcome reconcileWithCauchy(const MethodInput& in, Outcome huber, const CauchyFit& cauchy);

}  // namespace stac
