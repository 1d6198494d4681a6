// The sensors file (SPEC §3): YAML, both the seed and the calibration output.
#pragma once

#include <string>
#include <vector>

#include "stac/calibration.hpp"
#include "stac/log.hpp"
#include "stac/robot_model.hpp"
#include "stac/sensors.hpp"

namespace stac {

struct SensorsFile {
  SensorSet sensors;
  SensorParameters theta;
};

// Throws InputError(file, line, 0, "...key...") for every error in SPEC §3.
// `std`, `residual` and `summary` entries are accepted and ignored.
SensorsFile loadSensorsFile(const std::string& path, const RobotModel& model);
SensorsFile parseSensorsYaml(const std::string& text,
                             const std::string& source_name,
                             const RobotModel& model);

// The YAML text of a seed (result == nullptr) or of a calibration output.
std::string sensorsToYaml(const SensorSet& sensors,
                          const SensorParameters& theta,
                          const CalibrationResult* result = nullptr);

// SPEC §4 `stac_calib --joint-origins`: a free zero correction for each of
// `joints` (the one name "all": every movable joint that is not a mimic
// follower) that file->sensors does not list already. Throws
// std::invalid_argument naming a joint the URDF does not have.
void addJointOrigins(const RobotModel& model, const std::vector<std::string>& joints,
                     SensorsFile* file);

// SPEC §3 "Without a sensors file": infers sensors from the log header.
// Throws InputError naming the log and listing unplaceable columns with the
// closest joint or link name.
SensorsFile inferSensorsFromLog(const Log& log, const RobotModel& model);

}  // namespace stac
