// Pots on joints the log does not move (internal).
//
// A pot reads p = g q + b. Where its joint holds still through the log, its
// readings vary by their noise alone, and g (with b, which p's level ties
// to g q) is not in the data: any g fits, the frames' angles following.
// The local std cannot show this: the fitted angles still wander with the
// other sensors' noise, and against that wander the gain looks sharp (an
// unseen quadruped whose URDF gives its knees no range, so that the log
// held them still: a knee pot's gain 0.17 ± 0.015 where the truth's is
// 1.86, verdict ok). So such a pot's gain and bias are listed among the
// parameters the data cannot determine.
#pragma once

#include <vector>

#include "stac/calibration.hpp"
#include "stac/log.hpp"
#include "stac/measurement.hpp"

namespace stac {

// Readings whose std is at most this many times the sensor's seed σ come
// from a joint that holds still: a margin for a seed σ set too small (noise
// alone gives 1x; a third of a 0.5 rad range at a gain of 0.5 gives ~8x a
// 0.01 σ's).
constexpr double kStillSpread = 2.0;

// One entry per joint sensor with a free gain and a free bias whose
// readings in obs vary by at most kStillSpread times its σ in seed_noise.
std::vector<UnidentifiableDirection> stillJoints(const MeasurementModel& model,
                                                 const Observations& obs,
                                                 const NoiseModel& seed_noise);

}  // namespace stac
