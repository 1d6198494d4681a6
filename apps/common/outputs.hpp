// Output helpers shared by the apps.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "stac/log.hpp"
#include "stac/measurement.hpp"
#include "stac/robot_model.hpp"
#include "stac/sensors.hpp"

namespace stac::cli {

// Throws UsageError if an output would overwrite an input or another output.
void checkOutputs(const std::vector<std::string>& inputs,
                  const std::vector<std::pair<std::string, std::string>>& outputs);

// `time` (when the log has it), then one column per joint in q order.
std::string jointAnglesCsv(const RobotModel& robot, const Observations& obs, const RowMatrix& q);

struct ParameterChange {
  std::string name;
  double before = 0, after = 0;
  double score = 0;  // |after - before| in the parameter's typical units
};
// The n parameters whose values changed most between two θ.
std::vector<ParameterChange> largestChanges(const MeasurementModel& model,
                                            const SensorParameters& before,
                                            const SensorParameters& after, int n);

}  // namespace stac::cli
