// Whole turns a frame's joint sensors ask for (internal).
//
// A continuous joint (or one whose limits span more than a turn) puts every
// link at the same place at q and q ± 2π, so the markers cannot tell the
// two apart and a frame's local solver never crosses from one to the other:
// nothing in between fits better. Its pot can: a frame a turn off is 2π·gain
// off on it. Under a redescending loss (Cauchy) such a reading is ignored
// rather than pulled back, and an unseen Bravo 7 arm with gross readings
// converged with a continuous wrist a turn off in 18% of its frames, its
// pot's map fitted to the rest (silent). The q-phase therefore also tries,
// per frame, the whole turns that its pots' readings ask for, and keeps
// them when the frame's whole cost (every reading, under the loss) falls:
// a descent step of the same objective, which the local steps cannot take.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "stac/measurement.hpp"

namespace stac {

// A joint sensor on a joint that can turn a whole turn within [lower, upper].
struct TurnSensor {
  int sensor = 0;  // joint sensor index
  int column = 0;  // its q column
  double multiplier = 1.0, offset = 0.0;  // the sensed angle = multiplier q + offset
};

// The joint sensors on such joints whose column is not frozen (frozen: one
// flag per q column, or empty).
std::vector<TurnSensor> turnSensors(const MeasurementModel& model, const Eigen::VectorXd& lower,
                                    const Eigen::VectorXd& upper, const std::vector<bool>& frozen);

// The whole turns (at most kMaxTurns either way) that bring angle q to
// where `reading` puts it under `map`, if the reading then fits within
// kTurnFitSigma of its σ `sigma`; 0 when it would not, when the reading is
// missing, or when a turn moves the reading by less than kTurnInSigma σ.
// A map can be wrong (early in a run, or a wrong minimum), and frames
// free to take any turn can fit any map to within half a turn's worth of
// reading (an unseen Bravo 7 arm's wrist pot, its gain driven to 0 while
// the initialisation turned frames to fit its early map): so a frame is
// turned only onto a map that explains it, and only where a turn is too
// coarse for a wrong map to explain many frames by chance (a frame the map
// does not explain lands within the bound with odds 2·kTurnFitSigma /
// kTurnInSigma, 6%).
constexpr int kMaxTurns = 2;
constexpr double kTurnFitSigma = 3.0;
constexpr double kTurnInSigma = 100.0;
int turnsToFit(const TurnSensor& sensor, const GainBias& map, double sigma, double reading,
               double q);

}  // namespace stac
