#include "common/inputs.hpp"

#include <vector>

namespace stac::cli {
namespace {

// "a,b,c" -> {a, b, c}; an empty name (",," or a trailing comma) is a typo.
std::vector<std::string> nameList(const Args& args, const std::string& name) {
  std::vector<std::string> out;
  if (!args.has(name)) return out;
  const std::string v = args.get(name);
  size_t start = 0;
  while (true) {
    const size_t comma = v.find(',', start);
    const std::string item = v.substr(start, comma == std::string::npos ? comma : comma - start);
    if (item.empty()) throw UsageError(args.typed(name) + ": an empty column name");
    out.push_back(item);
    if (comma == std::string::npos) return out;
    start = comma + 1;
  }
}

}  // namespace

std::vector<std::string> ignoredColumns(const Args& args) {
  return nameList(args, "ignore-columns");
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
