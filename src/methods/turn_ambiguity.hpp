// Biases the data know only modulo a turn (internal).
//
// A revolute joint whose limits span more than a turn (a UR arm's ±2π) sees
// the same kinematics at q and q ± 2π. If the log's motion of that joint
// fits within the limits at more than one turn, nothing in the data tells
// the placements apart: the bias of its pots is known only modulo 2π·gain.
// The local std cannot show this (each placement is a sharp minimum), so
// it is listed among the parameters the data cannot determine.
#pragma once

#include <vector>

#include "stac/calibration.hpp"
#include "stac/log.hpp"
#include "stac/measurement.hpp"

namespace stac {

// One entry per joint sensor with a free bias on such a joint; q: the
// calibrated joint angles of every frame.
std::vector<UnidentifiableDirection> turnAmbiguities(const MeasurementModel& model,
                                                     const SensorParameters& theta,
                                                     const RowMatrix& q);

// A continuous joint is the same at q and q + 2πk, so its pots' biases are
// known only modulo 2π·gain, and which turn a calibration ends on is an
// accident of the start. Each is written as the one nearest zero, within
// half a turn (|bias| <= π·|gain|: the pot reads about zero near the
// joint's zero), the angles of that joint (q's column) moved by the same
// turns. Joints whose turns something else sees are left as they are: a
// pot with a held bias, a mimic follower (moved by multiplier·2πk), a
// coupling tendon (its length sums the angles).
void nearestTurnForContinuousJoints(const MeasurementModel& model, SensorParameters* theta,
                                    RowMatrix* q);

// A revolute joint is the same at q and q + 2πk, and a search that fits the
// markers alone (the wide basin's, wide_basin.hpp) can end on any turn;
// only the joint's limits tell them apart. The whole turns (0 or more
// either way) that leave the fewest of q column j's `angles` (NaN: none)
// beyond its URDF limits; ties: the fewest turns, so a motion already
// inside stays. 0 for a joint whose turns something else sees (as for
// nearestTurnForContinuousJoints), or without finite limits.
int turnsIntoLimits(const MeasurementModel& model, int j, const Eigen::VectorXd& angles);

}  // namespace stac
