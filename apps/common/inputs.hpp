// Input helpers shared by the apps that read a log: the sensors for it
// (from a sensors file or inferred from its header) and --ignore-columns.
#pragma once

#include <string>
#include <vector>

#include "common/cli.hpp"
#include "stac/log.hpp"
#include "stac/robot_model.hpp"
#include "stac/sensors_file.hpp"

namespace stac::cli {

// --ignore-columns a,b,… (SPEC §3): log columns that belong to no sensor.
Option ignoreColumnsOption();

// The columns of --ignore-columns; UsageError for an empty name.
std::vector<std::string> ignoredColumns(const Args& args);

// The sensors of `sensors_path`, or inferred from the log's header when it
// is "", with the columns of --ignore-columns added to those ignored.
SensorsFile sensorsForLog(const Args& args, const std::string& sensors_path,
                          const RobotModel& robot, const Log& log);

// bindLog against the file that defines the sensors (the log itself for
// inferred ones), pointing at its keys.
Observations bindSensors(const Log& log, const SensorsFile& sf, const std::string& sensors_path,
                         double mocap_scale);

}  // namespace stac::cli
