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
  ColumnKeys column_keys;  // where the file names each log column (empty if inferred)
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

// Adds `columns` (e.g. --ignore-columns, named by `origin` in messages) to
// the columns the sensors ignore. Throws InputError(sensors_source, ...) if
// a sensor reads one of them.
void ignoreColumns(SensorsFile* sf, const std::vector<std::string>& columns,
                   const std::string& origin, const std::string& sensors_source);

// bindLog (log.hpp) against a sensors file's sensors, its errors about a
// `column:` mapping pointing at that key and line of sensors_source.
Observations bindLog(const Log& log, const SensorsFile& sf, const std::string& sensors_source,
                     double mocap_scale);

// SPEC §3 "Without a sensors file": infers sensors from the log header,
// leaving out the columns in `ignore` (which the result then ignores).
// Throws InputError naming the log and listing unplaceable columns with the
// closest joint or link name when one is close; an <marker>@<link> column
// naming no link is an error too.
SensorsFile inferSensorsFromLog(const Log& log, const RobotModel& model,
                                const std::vector<std::string>& ignore = {});

}  // namespace stac
