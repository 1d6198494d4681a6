// Monolithic mode (--method joint): one Ceres problem over every q_t and θ
// (monolithic_problem.cpp).
#pragma once

#include "stac/calibrate.hpp"
#include "stac/measurement.hpp"
#include "solve/q_phase.hpp"

namespace stac {

// Solves for θ and every state->q at the given σ, from their values;
// options: max_iterations, tolerance, threads.
void solveMonolithic(const MeasurementModel& model, const NoiseModel& noise,
                       const RobustLoss& loss, const Observations& obs,
                       const CalibrationOptions& options, SensorParameters* theta,
                       QState* state, int* iterations, bool* converged);

}  // namespace stac
