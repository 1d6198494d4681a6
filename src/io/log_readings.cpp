// What a log must hold beyond well-formed rows: data rows at all, a frame
// with a reading, and (for a calibration) a reading of every sensor. Each
// failure is bad input (exit 2) that names the log, never a solve on
// nothing that ends in NaN or an arbitrary "estimate".
#include <cmath>
#include <string>
#include <vector>

#include "stac/error.hpp"
#include "stac/log.hpp"

namespace stac {
namespace {

bool anyReading(const RowMatrix& m, Eigen::Index t) {
  for (Eigen::Index c = 0; c < m.cols(); ++c)
    if (!std::isnan(m(t, c))) return true;
  return false;
}

bool columnRead(const RowMatrix& m, Eigen::Index c) {
  for (Eigen::Index t = 0; t < m.rows(); ++t)
    if (!std::isnan(m(t, c))) return true;
  return false;
}

// Every sensor and marker without a reading, as "joint sensor 'x'".
std::vector<std::string> unread(const Observations& obs, const SensorSet& sensors) {
  std::vector<std::string> out;
  for (size_t m = 0; m < sensors.markers.size(); ++m)
    if (!columnRead(obs.marker, static_cast<Eigen::Index>(3 * m)))  // x, y, z missing together
      out.push_back("marker '" + sensors.markers[m].name + "'");
  for (size_t s = 0; s < sensors.joint_sensors.size(); ++s)
    if (!columnRead(obs.joint, static_cast<Eigen::Index>(s)))
      out.push_back("joint sensor '" + sensors.joint_sensors[s].name + "'");
  for (size_t s = 0; s < sensors.tendon_sensors.size(); ++s)
    if (!columnRead(obs.tendon, static_cast<Eigen::Index>(s)))
      out.push_back("tendon sensor '" + sensors.tendon_sensors[s].name + "'");
  return out;
}

}  // namespace

void requireDataRows(const Log& log) {
  if (log.numFrames() == 0)
    throw InputError(log.path, log.header_line, 0,
                     "the log has no data rows (a header and nothing after it)");
}

void requireReadings(const Observations& obs, const SensorSet& sensors,
                     const std::string& log_path, ReadingCheck check) {
  const std::string frames = std::to_string(obs.num_frames) + " frame(s)";
  if (obs.num_frames == 0) throw InputError(log_path, "the log has no data rows");
  bool usable = false;
  for (Eigen::Index t = 0; t < obs.num_frames && !usable; ++t)
    usable = anyReading(obs.marker, t) || anyReading(obs.joint, t) || anyReading(obs.tendon, t);
  if (!usable)
    throw InputError(log_path, "no usable frame: every reading of the " + frames +
                                   " is empty (or nan)");
  if (check == ReadingCheck::kAnyFrame) return;
  const std::vector<std::string> missing = unread(obs, sensors);
  if (missing.empty()) return;
  std::string list;
  for (size_t i = 0; i < missing.size() && i < 20; ++i) list += (i ? ", " : "") + missing[i];
  if (missing.size() > 20) list += ", ... (" + std::to_string(missing.size()) + " in all)";
  throw InputError(log_path, "no reading at all in the " + frames + " for " + list +
                                 ": a calibration cannot estimate what nothing measures "
                                 "(give it readings, or remove it from the sensors)");
}

}  // namespace stac
