// Wide-basin initialisation of θ and q from the paper's seeding (internal).
#pragma once

#include <vector>

#include "stac/log.hpp"
#include "stac/measurement.hpp"
#include "stac/q_phase.hpp"

namespace stac {

// Frames used for initialising: at most this many, spread over the log.
constexpr int kInitFrames = 1000;

// Returns θ initialised from `theta` (the seed) on obs; state->q (one row per
// frame of obs, neutral on entry) receives the initial joint angles.
SensorParameters wideBasinInitialisation(const MeasurementModel& model, const Observations& obs,
                                         const NoiseModel& noise, const RobustLoss& loss,
                                         int threads, std::vector<FrameWorkspace>* ws,
                                         SensorParameters theta, QState* state,
                                         bool coupled_steps);

}  // namespace stac
