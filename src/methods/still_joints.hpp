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
// from a joint that holds still: room for a seed σ a quarter too small
// (noise alone gives 1x). Not more: a joint that moves by less than its
// pot's noise over hundreds of frames still sets the gain (the bundled
// hand's narrow abductions on partial swings read 1.75-2x, their gains
// within their std; at 2x they were listed).
constexpr double kStillSpread = 1.25;
constexpr double kStillFittedCap = 2.0;

// One entry per joint sensor with a free gain and a free bias whose
// readings in obs vary by at most kStillSpread times its σ (or, over few
// readings, by at most what noise alone gives with 3 std of its variance's
// sampling spread, √(2/n) σ²). Its σ: the larger of the seed's and the
// fitted one (`fitted_noise`: the seed's scaled by its group's fitted
// factor κ; empty: the seed's), the fitted one counted up to
// kStillFittedCap times the seed's. A seed σ too small for the whole group
// would otherwise hide a still pot; the seed's is the floor because κ
// shrinks where the group's pots' residuals do (angles nothing else sees
// fit their pots exactly); and the cap keeps a κ inflated by a wrong
// minimum (the verdict allows up to 3x) from listing joints that move.
std::vector<UnidentifiableDirection> stillJoints(const MeasurementModel& model,
                                                 const Observations& obs,
                                                 const NoiseModel& seed_noise,
                                                 const NoiseModel& fitted_noise);

}  // namespace stac
