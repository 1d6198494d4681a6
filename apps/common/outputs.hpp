// Output helpers shared by the apps.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "stac/log.hpp"
#include "stac/robot_model.hpp"
#include "stac/sensors.hpp"

namespace stac::cli {

// Throws UsageError if an output (flag, path) would overwrite an input or
// another output (compared as files and as normalised paths), is a
// directory, or lies in a folder that does not exist.
void checkOutputs(const std::vector<std::string>& inputs,
                  const std::vector<std::pair<std::string, std::string>>& outputs);

// writeFileAtomically, with a failure reported as bad input (exit 2).
void writeOutput(const std::string& path, const std::string& content);
void writeLogOutput(const std::string& path, const Log& log);

}  // namespace stac::cli
