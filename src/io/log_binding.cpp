// The log's columns handed out to the sensors that read them (SPEC §2, §3):
// each sensor's column(s) by its name or its `column:`/`columns:`, the
// ignored columns set aside, and every mismatch reported at once.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <set>

#include "io/closest_name.hpp"
#include "stac/error.hpp"
#include "stac/log.hpp"
#include "stac/sensors_file.hpp"

namespace stac {
namespace {

// The log's columns by name, handed out to the sensors that read them. It
// notes what was taken and what the log lacks, so that one error can list
// every mismatch at once.
class ColumnTaker {
 public:
  explicit ColumnTaker(const std::vector<std::string>& columns) {
    for (size_t c = 0; c < columns.size(); ++c) column_[columns[c]] = static_cast<int>(c);
  }

  // The column's index, or -1 (and the name noted as missing).
  int take(const std::string& name) {
    auto it = column_.find(name);
    if (it == column_.end()) {
      missing_.push_back(name);
      return -1;
    }
    used_.insert(name);
    return it->second;
  }

  // Sets an ignored column aside (one the log lacks is no error: one
  // sensors file serves logs with and without it). False if a sensor has
  // taken it.
  bool ignore(const std::string& name) {
    if (used_.count(name)) return false;
    if (column_.count(name)) used_.insert(name);
    return true;
  }

  const std::vector<std::string>& missing() const { return missing_; }

  std::vector<std::string> unused(const std::vector<std::string>& columns) const {
    std::vector<std::string> extra;
    for (const std::string& c : columns)
      if (!used_.count(c)) extra.push_back(c);
    return extra;
  }

 private:
  std::map<std::string, int> column_;
  std::set<std::string> used_;
  std::vector<std::string> missing_;
};

// Marker m's x, y, z into columns 3m..3m+2 of *out, in metres; a marker
// missing any coordinate is missing as a whole (SPEC §2).
void bindMarkers(const Log& log, const std::vector<MarkerConfig>& markers, double mocap_scale,
                 ColumnTaker& columns, RowMatrix* out) {
  for (size_t m = 0; m < markers.size(); ++m) {
    const std::array<std::string, 3> names = markers[m].logColumns();
    const int cx = columns.take(names[0]);
    const int cy = columns.take(names[1]);
    const int cz = columns.take(names[2]);
    if (cx < 0 || cy < 0 || cz < 0) continue;
    for (int t = 0; t < log.numFrames(); ++t) {
      const double x = log.values(t, cx), y = log.values(t, cy), z = log.values(t, cz);
      const bool miss = std::isnan(x) || std::isnan(y) || std::isnan(z);
      const double nan = std::numeric_limits<double>::quiet_NaN();
      (*out)(t, 3 * m) = miss ? nan : x * mocap_scale;
      (*out)(t, 3 * m + 1) = miss ? nan : y * mocap_scale;
      (*out)(t, 3 * m + 2) = miss ? nan : z * mocap_scale;
    }
  }
}

// Joint or tendon sensors: one column each, sensor s into column s of *out.
// Element by element: no Eigen column of a matrix that may have no rows.
template <class SensorConfig>
void bindScalarSensors(const Log& log, const std::vector<SensorConfig>& sensors,
                       ColumnTaker& columns, RowMatrix* out) {
  for (size_t s = 0; s < sensors.size(); ++s) {
    const int c = columns.take(sensors[s].logColumn());
    if (c < 0) continue;
    for (int t = 0; t < log.numFrames(); ++t) (*out)(t, s) = log.values(t, c);
  }
}

// Names for an error message, cut short so that a wide log stays readable.
std::string nameList(const std::vector<std::string>& v) {
  constexpr size_t kShown = 30;
  std::string s;
  for (size_t i = 0; i < v.size() && i < kShown; ++i) s += (i ? ", " : "") + v[i];
  if (v.size() > kShown) s += ", ... (" + std::to_string(v.size()) + " in all)";
  return s;
}

// Both directions of a log/sensors mismatch in one sentence; "" if none.
std::string columnMismatch(const std::vector<std::string>& missing,
                           const std::vector<std::string>& extra,
                           const std::string& sensors_source) {
  std::string problem;
  if (!missing.empty())
    problem = "the log has no column for " + nameList(missing) + " (sensors defined in " +
              sensors_source + ")";
  if (!extra.empty())
    problem += (problem.empty() ? "" : "; ") + std::string("column(s) ") + nameList(extra) +
               " belong to no sensor in " + sensors_source +
               " (list bookkeeping columns in ignore_columns)";
  return problem;
}

// A column that a `column:`/`columns:` entry names and the log lacks is the
// sensors file's error, at that key; the closest log column as a hint.
void requireMappedColumns(const Log& log, const std::vector<std::string>& missing,
                          const ColumnKeys& keys, const std::string& sensors_source) {
  for (const std::string& c : missing) {
    const auto it = keys.find(c);
    if (it == keys.end() || !it->second.mapped) continue;
    const std::optional<std::string> near = closestName(c, log.columns);
    throw InputError(sensors_source, it->second.line, 0,
                     "key '" + it->second.key + "': the log " + log.path + " has no column '" +
                         c + "'" + (near ? "; did you mean '" + *near + "'?" : ""));
  }
}

}  // namespace

Observations bindLog(const Log& log, const SensorSet& sensors, const std::string& sensors_source,
                     double mocap_scale, const ColumnKeys& keys) {
  const int T = log.numFrames();
  Observations obs;
  obs.num_frames = T;
  obs.time = log.time;
  obs.time_name = log.time_name;
  obs.marker.resize(T, 3 * static_cast<Eigen::Index>(sensors.markers.size()));
  obs.joint.resize(T, static_cast<Eigen::Index>(sensors.joint_sensors.size()));
  obs.tendon.resize(T, static_cast<Eigen::Index>(sensors.tendon_sensors.size()));
  ColumnTaker columns(log.columns);
  bindMarkers(log, sensors.markers, mocap_scale, columns, &obs.marker);
  bindScalarSensors(log, sensors.joint_sensors, columns, &obs.joint);
  bindScalarSensors(log, sensors.tendon_sensors, columns, &obs.tendon);
  for (const std::string& c : sensors.ignore_columns)
    if (!columns.ignore(c))
      throw InputError(sensors_source, "column '" + c +
                                           "' is both read by a sensor and ignored: a column is "
                                           "a sensor's or ignored, not both");
  requireMappedColumns(log, columns.missing(), keys, sensors_source);
  const std::string problem =
      columnMismatch(columns.missing(), columns.unused(log.columns), sensors_source);
  if (!problem.empty()) throw InputError(log.path, log.header_line, 0, problem);
  requireDataRows(log);  // after the header's check, which has more to say
  return obs;
}

namespace {

// Who reads `column` in sf, as "key 'joint_sensors[0].column' (line 7)".
std::string readerOf(const SensorsFile& sf, const std::string& column) {
  const auto it = sf.column_keys.find(column);
  if (it != sf.column_keys.end())
    return "key '" + it->second.key + "' (line " + std::to_string(it->second.line) + ")";
  return "a sensor";
}

bool isRead(const SensorSet& s, const std::string& column) {
  for (const MarkerConfig& m : s.markers)
    for (const std::string& c : m.logColumns())
      if (c == column) return true;
  for (const JointSensorConfig& j : s.joint_sensors)
    if (j.logColumn() == column) return true;
  for (const TendonSensorConfig& t : s.tendon_sensors)
    if (t.logColumn() == column) return true;
  return false;
}

}  // namespace

Observations bindLog(const Log& log, const SensorsFile& sf, const std::string& sensors_source,
                     double mocap_scale) {
  return bindLog(log, sf.sensors, sensors_source, mocap_scale, sf.column_keys);
}

void ignoreColumns(SensorsFile* sf, const std::vector<std::string>& columns,
                   const std::string& origin, const std::string& sensors_source) {
  std::vector<std::string>& ignored = sf->sensors.ignore_columns;
  for (const std::string& c : columns) {
    if (isRead(sf->sensors, c))
      throw InputError(sensors_source, origin + " lists column '" + c + "', which " +
                                           readerOf(*sf, c) +
                                           " reads: a column is a sensor's or ignored, not both");
    if (std::find(ignored.begin(), ignored.end(), c) == ignored.end()) ignored.push_back(c);
  }
}

}  // namespace stac
