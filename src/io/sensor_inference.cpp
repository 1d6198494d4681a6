// Sensors inferred from a log header (SPEC §3 "Without a sensors file"): a
// column named after a movable joint is a joint sensor on it, columns
// <link>.x/.y/.z are a marker on that link, <marker>@<link>.x/.y/.z a marker
// named <marker> on that link, ignored columns are left alone, and any other
// column is an error that suggests a joint or link name when one is close.
#include <algorithm>
#include <array>
#include <map>
#include <set>
#include <utility>

#include "io/closest_name.hpp"
#include "stac/error.hpp"
#include "stac/sensors_file.hpp"

namespace stac {
namespace {

// The seeds SPEC §3 gives to inferred sensors.
constexpr double kJointSigma = 0.01;
constexpr double kMarkerSigma = 0.002;  // metres

// "l_forearm.x" -> "l_forearm"; "" if the column has no .x/.y/.z suffix.
std::string markerBase(const std::string& column) {
  const auto dot = column.rfind('.');
  if (dot == std::string::npos || dot == 0 || dot + 2 != column.size()) return "";
  const char axis = column[dot + 1];
  return axis == 'x' || axis == 'y' || axis == 'z' ? column.substr(0, dot) : "";
}

// A marker base "p1@wrist" split into its marker ("p1") and link
// ("wrist") at the last '@'; a base without '@' names both after the link.
struct MarkerBase {
  std::string marker, link;
  bool at = false;  // written <marker>@<link>
};

MarkerBase splitBase(const std::string& base) {
  const auto at = base.rfind('@');
  if (at == std::string::npos) return {base, base, false};
  return {base.substr(0, at), base.substr(at + 1), true};
}

// A joint sensor named after its joint and its column: gain 1, bias 0.
void addJointSensor(const std::string& column, int joint, SensorsFile* out) {
  JointSensorConfig s;
  s.name = column;
  s.joint_name = column;
  s.joint = joint;
  s.sigma = kJointSigma;
  out->sensors.joint_sensors.push_back(s);
  out->theta.joint_sensor.push_back({1.0, 0.0});
}

// A marker seeded at the link's origin, reading the columns <base>.x/.y/.z
// (written out only when they are not the marker's default).
void addMarker(const MarkerBase& mb, const std::string& base, int link, SensorsFile* out) {
  MarkerConfig m;
  m.name = mb.marker;
  m.link_name = mb.link;
  m.link = link;
  m.sigma = out->sensors.mocap_sigma;
  if (mb.at) m.columns = {base + ".x", base + ".y", base + ".z"};
  out->sensors.markers.push_back(m);
  out->theta.marker_position.push_back(Eigen::Vector3d::Zero());
}

// Adds a sensor for every column that names one and returns the columns so
// placed. A joint comes first: a joint named like a marker column keeps it.
// Names stay unique: a second marker of one name is left unplaced.
std::set<std::string> placeColumns(const Log& log, const RobotModel& model,
                                   const std::set<std::string>& ignored, SensorsFile* out) {
  const std::set<std::string> columns(log.columns.begin(), log.columns.end());
  std::set<std::string> placed, names;
  for (const std::string& c : log.columns) {
    if (placed.count(c) || ignored.count(c)) continue;
    if (const auto j = model.movableJointIndex(c)) {
      addJointSensor(c, *j, out);
      placed.insert(c);
      names.insert(c);
      continue;
    }
    const std::string base = markerBase(c);
    const MarkerBase mb = splitBase(base);
    if (base.empty() || mb.marker.empty() || names.count(mb.marker)) continue;
    const auto link = model.linkIndex(mb.link);
    if (!link) continue;
    const std::array<std::string, 3> xyz = {base + ".x", base + ".y", base + ".z"};
    bool free = true;
    for (const std::string& a : xyz)
      free = free && columns.count(a) && !placed.count(a) && !ignored.count(a);
    if (!free) continue;
    addMarker(mb, base, *link, out);
    placed.insert(xyz.begin(), xyz.end());
    names.insert(mb.marker);
  }
  return placed;
}

std::vector<std::string> jointNames(const RobotModel& model) {
  std::vector<std::string> out;
  for (const MovableJoint& j : model.movableJoints()) out.push_back(j.name);
  return out;
}

std::vector<std::string> linkNames(const RobotModel& model) {
  std::vector<std::string> out;
  for (const Link& l : model.links()) out.push_back(l.name);
  return out;
}

const char* const kNothingClose = "no joint or link name is close";

// A hint for a column without .x/.y/.z: a joint first (the column is most
// likely a joint reading), else a link (whose marker needs .x/.y/.z).
std::string jointColumnHint(const std::string& c, const RobotModel& model) {
  if (const auto j = closestName(c, jointNames(model)))
    return "closest joint or link: joint '" + *j + "'; did you mean '" + *j + "'?";
  if (const auto l = closestName(c, linkNames(model)))
    return "closest joint or link: link '" + *l + "', whose marker takes the columns " + *l +
           ".x, " + *l + ".y and " + *l + ".z";
  return kNothingClose;
}

// A hint for a marker column (base: its name without .x/.y/.z).
std::string markerColumnHint(const std::string& c, const std::string& base,
                             const RobotModel& model, const std::set<std::string>& columns) {
  const MarkerBase mb = splitBase(base);
  const std::string axis = c.substr(base.size());
  if (mb.at && mb.marker.empty()) return "no marker name before the '@'";
  if (model.linkIndex(mb.link)) {
    if (columns.count(base + ".x") && columns.count(base + ".y") && columns.count(base + ".z"))
      return "marker name '" + mb.marker + "' is another sensor's or marker's already";
    return "a marker on link '" + mb.link + "' needs all of " + base + ".x, " + base + ".y and " +
           base + ".z";
  }
  const std::optional<std::string> l = closestName(mb.link, linkNames(model));
  const std::string prefix = mb.at ? mb.marker + "@" : "";
  if (mb.at)
    return "no link '" + mb.link + "' in " + model.sourceName() +
           (l ? "; did you mean '" + prefix + *l + axis + "'?" : "");
  if (l) return "closest joint or link: link '" + *l + "'; did you mean '" + *l + axis + "'?";
  return kNothingClose;
}

// Why an unplaced column is not a sensor, as specific as the model allows.
std::string unplacedHint(const std::string& c, const RobotModel& model,
                         const std::set<std::string>& columns) {
  const std::string base = markerBase(c);
  if (!base.empty()) return markerColumnHint(c, base, model, columns);
  const auto& all_joints = model.allJointNames();
  if (std::find(all_joints.begin(), all_joints.end(), c) != all_joints.end())
    return "joint '" + c + "' is fixed: it has no angle to sense";
  return jointColumnHint(c, model);
}

}  // namespace

SensorsFile inferSensorsFromLog(const Log& log, const RobotModel& model,
                                const std::vector<std::string>& ignore) {
  SensorsFile out;
  out.sensors.mocap_sigma = kMarkerSigma;
  out.sensors.ignore_columns = ignore;
  const std::set<std::string> ignored(ignore.begin(), ignore.end());
  const std::set<std::string> placed = placeColumns(log, model, ignored, &out);

  // Every other column is an error; each gets a hint.
  const std::set<std::string> columns(log.columns.begin(), log.columns.end());
  std::string unplaced;
  int count = 0;
  bool far = false;
  for (const std::string& c : log.columns) {
    if (placed.count(c) || ignored.count(c)) continue;
    ++count;
    const std::string hint = unplacedHint(c, model, columns);
    far = far || hint == kNothingClose;
    unplaced += "\n  " + c + " (" + hint + ")";
  }
  if (far)
    unplaced +=
        "\nA column that belongs to no sensor (bookkeeping) can be ignored: --ignore-columns, "
        "or ignore_columns: in a sensors file; one that holds a marker coordinate can be "
        "named <marker>@<link>.x/.y/.z, or mapped with columns: in a sensors file.";
  if (count > 0)
    throw InputError(log.path, log.header_line, 0,
                     std::to_string(count) + " column(s) name no movable joint of " +
                         model.sourceName() +
                         " and no marker (<link>.x/.y/.z or <marker>@<link>.x/.y/.z), so no "
                         "sensor could be inferred for them (give a sensors file with "
                         "--sensors):" +
                         unplaced);
  if (out.sensors.joint_sensors.empty() && out.sensors.markers.empty())
    throw InputError(log.path, log.header_line, 0,
                     "the log has no sensor columns to infer sensors from");
  return out;
}

}  // namespace stac
