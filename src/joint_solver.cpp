// Placeholder until the monolithic solver lands.
#include <stdexcept>

#include "stac/calibrate.hpp"
#include "stac/q_phase.hpp"

namespace stac {
void solveJointProblem(const MeasurementModel&, const NoiseModel&, const RobustLoss&,
                       const Observations&, const CalibrationOptions&, SensorParameters*,
                       QState*, int*, bool*) {
  throw std::logic_error("--method joint is not implemented yet");
}
}  // namespace stac
