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

}  // namespace stac
