// A small arm built in code with known sensor parameters and simulated
// readings, for solver tests that must not depend on data/ files.
#pragma once

#include <random>
#include <string>
#include <utility>
#include <vector>

#include "stac/log.hpp"
#include "stac/measurement.hpp"
#include "stac/robot_model.hpp"
#include "stac/sensors.hpp"

namespace stac::test {

struct ArmProblem {
  RobotModel robot;
  SensorSet sensors;
  SensorParameters truth, seed;
  RowMatrix q_true;
  Observations obs;
};

// 4-DoF arm (non-parallel adjacent axes), a pot on every joint, a 2-point
// linear pot across joints 2-3, markers on the base, link 2 and link 4. The
// base marker and one marker on link 4 are fixed at their true positions:
// that removes the two gauge freedoms (mocap rotation about j1 vs j1's bias;
// j4's bias vs the free markers on link 4).
// `noise_seed` (default: seed) draws the noise alone, so that several noise
// draws can share one truth.
ArmProblem makeArmProblem(int frames, unsigned seed, double noise_scale = 1.0,
                          double dropout = 0.0, int noise_seed = -1);

// Replaces a fraction of all readings by gross errors (20-60 σ for a scalar,
// 5-20 cm for a marker); returns (frame, sensor name) of each.
std::vector<std::pair<int, std::string>> addOutliers(const SensorSet& sensors, double fraction,
                                                     unsigned seed, Observations* obs);

// Fills obs with readings predicted from truth at q, plus Gaussian noise.
void simulateReadings(const MeasurementModel& model, const SensorParameters& truth,
                      const RowMatrix& q, double noise_scale, double dropout,
                      std::mt19937& rng, Observations* obs);

}  // namespace stac::test
