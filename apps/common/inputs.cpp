#include "common/inputs.hpp"

#include <vector>

namespace stac::cli {

std::vector<std::string> ignoredColumns(const Args& args) {
  return args.getList("ignore-columns", "column name");
}

Option ignoreColumnsOption() {
  return {"ignore-columns", "A,B,...",
          "log columns that belong to no sensor (bookkeeping); adds to the sensors file's "
          "ignore_columns"};
}

SensorsFile sensorsForLog(const Args& args, const std::string& sensors_path,
                          const RobotModel& robot, const Log& log) {
  const std::vector<std::string> ignore = ignoredColumns(args);
  if (sensors_path.empty()) return inferSensorsFromLog(log, robot, ignore);
  SensorsFile sf = loadSensorsFile(sensors_path, robot);
  ignoreColumns(&sf, ignore, "--ignore-columns", sensors_path);
  return sf;
}

Observations bindSensors(const Log& log, const SensorsFile& sf, const std::string& sensors_path,
                         double mocap_scale) {
  return bindLog(log, sf, sensors_path.empty() ? log.path : sensors_path, mocap_scale);
}

}  // namespace stac::cli
