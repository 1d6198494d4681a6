// Output helpers shared by the apps.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "stac/log.hpp"
#include "stac/robot_model.hpp"
#include "stac/sensors.hpp"
#include "stac/theta_space.hpp"

namespace stac::cli {

// Throws UsageError if an output (flag, path) would overwrite an input or
// another output (compared as files and as normalised paths), is a
// directory, or lies in a folder that does not exist.
void checkOutputs(const std::vector<std::string>& inputs,
                  const std::vector<std::pair<std::string, std::string>>& outputs);

// writeFileAtomically, with a failure reported as bad input (exit 2).
void writeOutput(const std::string& path, const std::string& content);
void writeLogOutput(const std::string& path, const Log& log);

struct ParameterChange {
  std::string name;
  double before = 0, after = 0;
  double score = 0;  // |after - before| in the parameter's typical units
};
// The n parameters whose values changed most between two θ.
std::vector<ParameterChange> largestChanges(const ThetaSpace& space,
                                            const SensorParameters& before,
                                            const SensorParameters& after, int n);

}  // namespace stac::cli
