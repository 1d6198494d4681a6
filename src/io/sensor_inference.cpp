// Sensors inferred from a log header (SPEC §3 "Without a sensors file"): a
// column named after a movable joint is a joint sensor on it, columns
// <link>.x/.y/.z are a marker on that link, and any other column is an error
// that suggests the closest joint or link name.
#include <algorithm>
#include <set>
#include <utility>

#include "stac/error.hpp"
#include "stac/sensors_file.hpp"

namespace stac {
namespace {

// The seeds SPEC §3 gives to inferred sensors.
constexpr double kJointSigma = 0.01;
constexpr double kMarkerSigma = 0.002;  // metres

size_t editDistance(const std::string& a, const std::string& b) {
  std::vector<size_t> prev(b.size() + 1), cur(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) prev[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    cur[0] = i;
    for (size_t j = 1; j <= b.size(); ++j)
      cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + (a[i - 1] != b[j - 1])});
    std::swap(prev, cur);
  }
  return prev[b.size()];
}

// "l_forearm.x" -> "l_forearm"; "" if the column has no .x/.y/.z suffix.
std::string markerBase(const std::string& column) {
  const auto dot = column.rfind('.');
  if (dot == std::string::npos || dot == 0 || dot + 2 != column.size()) return "";
  const char axis = column[dot + 1];
  return axis == 'x' || axis == 'y' || axis == 'z' ? column.substr(0, dot) : "";
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

// A marker named after its link, seeded at the link's origin.
void addMarker(const std::string& link_name, int link, SensorsFile* out) {
  MarkerConfig m;
  m.name = link_name;
  m.link_name = link_name;
  m.link = link;
  m.sigma = out->sensors.mocap_sigma;
  out->sensors.markers.push_back(m);
  out->theta.marker_position.push_back(Eigen::Vector3d::Zero());
}

// Adds a sensor for every column that names one and returns the columns so
// placed. A joint comes first: a joint named like a marker column keeps it.
std::set<std::string> placeColumns(const Log& log, const RobotModel& model, SensorsFile* out) {
  const std::set<std::string> columns(log.columns.begin(), log.columns.end());
  std::set<std::string> placed;
  for (const std::string& c : log.columns) {
    if (placed.count(c)) continue;
    if (const auto j = model.movableJointIndex(c)) {
      addJointSensor(c, *j, out);
      placed.insert(c);
      continue;
    }
    const std::string base = markerBase(c);
    if (base.empty()) continue;
    const auto link = model.linkIndex(base);
    if (!link) continue;
    const std::string x = base + ".x", y = base + ".y", z = base + ".z";
    if (!columns.count(x) || !columns.count(y) || !columns.count(z)) continue;
    if (placed.count(x) || placed.count(y) || placed.count(z)) continue;  // a joint took one
    addMarker(base, *link, out);
    placed.insert({x, y, z});
  }
  return placed;
}

using Candidate = std::pair<std::string, std::string>;  // (name, "joint" or "link")

std::vector<Candidate> nameCandidates(const RobotModel& model) {
  std::vector<Candidate> candidates;
  for (const MovableJoint& j : model.movableJoints()) candidates.emplace_back(j.name, "joint");
  for (const Link& l : model.links()) candidates.emplace_back(l.name, "link");
  return candidates;
}

// The closest joint or link name to an unplaced column (base: its marker
// base, "" if it has none), spelled as the column the user may have meant.
std::string closestNameHint(const std::string& c, const std::string& base,
                            const std::vector<Candidate>& candidates) {
  const std::string key = base.empty() ? c : base;
  const Candidate* best = nullptr;
  size_t best_d = std::string::npos;
  for (const Candidate& cand : candidates) {
    // A column with an .x/.y/.z suffix is meant as a marker: on a link.
    if (!base.empty() && cand.second != "link") continue;
    const size_t d = editDistance(key, cand.first);
    if (d < best_d) best_d = d, best = &cand;
  }
  if (!best) return "the robot has no joint or link to match";
  return "closest joint or link: " + best->second + " '" + best->first + "'; did you mean '" +
         (base.empty() || best->second != "link" ? best->first
                                                  : best->first + c.substr(base.size())) +
         "'?";
}

// Why an unplaced column is not a sensor, as specific as the model allows.
std::string unplacedHint(const std::string& c, const RobotModel& model,
                         const std::vector<Candidate>& candidates) {
  const std::string base = markerBase(c);
  if (!base.empty() && model.linkIndex(base))
    return "a marker on link '" + base + "' needs all of " + base + ".x, " + base + ".y and " +
           base + ".z";
  const auto& all_joints = model.allJointNames();
  if (std::find(all_joints.begin(), all_joints.end(), c) != all_joints.end())
    return "joint '" + c + "' is fixed: it has no angle to sense";
  return closestNameHint(c, base, candidates);
}

}  // namespace

SensorsFile inferSensorsFromLog(const Log& log, const RobotModel& model) {
  SensorsFile out;
  out.sensors.mocap_sigma = kMarkerSigma;
  const std::set<std::string> placed = placeColumns(log, model, &out);

  // Every other column is an error; each gets the closest name as a hint.
  const std::vector<Candidate> candidates = nameCandidates(model);
  std::string unplaced;
  int count = 0;
  for (const std::string& c : log.columns) {
    if (placed.count(c)) continue;
    ++count;
    unplaced += "\n  " + c + " (" + unplacedHint(c, model, candidates) + ")";
  }
  if (count > 0)
    throw InputError(log.path, log.header_line, 0,
                     std::to_string(count) +
                         " column(s) name no movable joint of " + model.sourceName() +
                         " and no link's marker (<link>.x/.y/.z), so no sensor could be "
                         "inferred for them (give a sensors file with --sensors):" +
                         unplaced);
  if (out.sensors.joint_sensors.empty() && out.sensors.markers.empty())
    throw InputError(log.path, log.header_line, 0,
                     "the log has no sensor columns to infer sensors from");
  return out;
}

}  // namespace stac
