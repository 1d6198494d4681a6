// The sensors file's writer (SPEC §3): hand-written, so that its numbers are
// ones both YAML 1.1 and 1.2 readers take as floats and that round-trip
// exactly, and so that the layout is the one the SPEC shows.
#include "stac/sensors_file.hpp"

#include <algorithm>
#include <array>
#include <cassert>
#include <cctype>
#include <set>

#include "io/quoted.hpp"
#include "io/rpy.hpp"
#include "stac/file_io.hpp"

namespace stac {
namespace {

std::string num(double v) { return formatNumber(v); }

std::string vec(const Eigen::Ref<const Eigen::VectorXd>& v) {
  std::string s = "[";
  for (Eigen::Index i = 0; i < v.size(); ++i) s += (i ? ", " : "") + num(v[i]);
  return s + "]";
}

// A YAML double-quoted string.
std::string quoted(const std::string& s) { return doubleQuoted(s, QuoteStyle::kYaml); }

// A name as a plain scalar when that is unambiguous in YAML 1.1 and 1.2 (no
// number, bool or null look-alike, no indicator characters), else quoted.
std::string scalar(const std::string& s) {
  static const std::set<std::string> kReserved = {"y", "n", "yes", "no", "on", "off",
                                                  "true", "false", "null", "~"};
  std::string lower(s);
  for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  const bool plain =
      !s.empty() && (std::isalpha(static_cast<unsigned char>(s[0])) || s[0] == '_') &&
      std::all_of(s.begin(), s.end(),
                  [](char c) {
                    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.' ||
                           c == '-' || c == '/';
                  }) &&
      !kReserved.count(lower);
  return plain ? s : quoted(s);
}

// A flow list of names: [a, "b@c.x"].
template <class Names>
std::string list(const Names& names) {
  std::string s = "[";
  for (const std::string& n : names) s += (s.size() > 1 ? ", " : "") + scalar(n);
  return s + "]";
}

const char* boolean(bool b) { return b ? "true" : "false"; }

// `fixed` as it reads back: true or false when every part or none is held,
// else the list of the held parts (SPEC §3).
std::string fixedValue(bool first, bool second, const char* first_name, const char* second_name) {
  if (first == second) return boolean(first);
  return std::string("[") + (first ? first_name : second_name) + "]";
}

std::string residualLine(const std::string& indent, const ResidualStats& r) {
  return indent + "residual: {rms: " + num(r.rms) + ", mae: " + num(r.mae) +
         ", count: " + std::to_string(r.count) + "}\n";
}

// {marker: …, joint: …, tendon: …} over the groups present.
std::string perGroup(const CalibrationSummary& sm, const double (&v)[kNumSensorGroups]) {
  std::string s = "{";
  bool first = true;
  for (int g = 0; g < kNumSensorGroups; ++g) {
    if (!sm.group_present[g]) continue;
    s += (first ? "" : ", ") + std::string(groupName(static_cast<SensorGroup>(g))) + ": " +
         num(v[g]);
    first = false;
  }
  return s + "}";
}

// Appends the sections of one sensors file, each in the order the SPEC
// shows. σ are the calibration's (adapted) values when there is one, and
// std/residual/summary are written only then.
class Writer {
 public:
  Writer(const SensorSet& s, const SensorParameters& th, const CalibrationResult* result)
      : s_(s), th_(th), result_(result), sig_(result ? result->sensors : s) {
    assert(sig_.markers.size() == s.markers.size());
    assert(sig_.joint_sensors.size() == s.joint_sensors.size());
    assert(sig_.tendon_sensors.size() == s.tendon_sensors.size());
    assert(th.marker_position.size() == s.markers.size());
    assert(th.joint_sensor.size() == s.joint_sensors.size());
    assert(th.tendon_sensor.size() == s.tendon_sensors.size());
  }

  void mocap(std::string& o) const {
    o += "mocap:\n";
    o += "  sigma: " + num(sig_.mocap_sigma) + "\n";
    frame(o);
    o += "  markers:\n";
    for (size_t m = 0; m < s_.markers.size(); ++m) marker(o, m);
  }

  void jointSensors(std::string& o) const {
    o += "joint_sensors:\n";
    for (size_t j = 0; j < s_.joint_sensors.size(); ++j) {
      const JointSensorConfig& c = s_.joint_sensors[j];
      o += "  - name: " + scalar(c.name) + "\n";
      o += "    joint: " + scalar(c.joint_name) + "\n";
      column(o, c.name, c.column);
      gainBias(o, th_.joint_sensor[j], sig_.joint_sensors[j].sigma, c.fixed);
      if (result_) extras(o, result_->std.joint_sensor, result_->joint_residual, j);
    }
  }

  void tendonSensors(std::string& o) const {
    o += "tendon_sensors:\n";
    for (size_t j = 0; j < s_.tendon_sensors.size(); ++j) {
      const TendonSensorConfig& c = s_.tendon_sensors[j];
      o += "  - name: " + scalar(c.name) + "\n";
      column(o, c.name, c.column);
      gainBias(o, th_.tendon_sensor[j], sig_.tendon_sensors[j].sigma, c.fixed);
      if (c.kind == TendonSensorConfig::Kind::kPath)
        tendonPath(o, c);
      else
        tendonCoupling(o, c);
      if (result_) extras(o, result_->std.tendon_sensor, result_->tendon_residual, j);
    }
  }

 private:
  // Both rpy and quaternion, so that a reader may take either (SPEC §3).
  void frame(std::string& o) const {
    const Eigen::Quaterniond q = unitQuaternion(th_.mocap.rotation);
    o += "  frame:\n";
    o += "    translation: " + vec(th_.mocap.translation) + "\n";
    o += "    rpy: " + vec(toRpy(q)) + "\n";
    o += "    quaternion: " + vec(Eigen::Vector4d(q.w(), q.x(), q.y(), q.z())) + "\n";
    const FixedFrame& fixed = s_.mocap_frame_fixed;
    o += "    fixed: " + fixedValue(fixed.rotation, fixed.translation, "rotation", "translation") +
         "\n";
    if (result_)
      o += "    std: {translation: " + vec(result_->std.mocap_translation) +
           ", rotation: " + vec(result_->std.mocap_rotation) + "}\n";
  }

  // A marker's own σ only where it differs from mocap.sigma (or was given),
  // so that a seed written back reads as it was.
  void marker(std::string& o, size_t m) const {
    const MarkerConfig& mc = s_.markers[m];
    o += "    - name: " + scalar(mc.name) + "\n";
    o += "      link: " + scalar(mc.link_name) + "\n";
    const std::array<std::string, 3> xyz = mc.logColumns();
    if (xyz[0] != mc.name + ".x" || xyz[1] != mc.name + ".y" || xyz[2] != mc.name + ".z")
      o += "      columns: " + list(xyz) + "\n";
    o += "      position: " + vec(th_.marker_position[m]) + "\n";
    o += "      fixed: " + std::string(boolean(mc.fixed)) + "\n";
    const MarkerConfig& ms = sig_.markers[m];
    if (ms.sigma_overridden || ms.sigma != sig_.mocap_sigma)
      o += "      sigma: " + num(ms.sigma) + "\n";
    if (result_) {
      if (m < result_->std.marker_position.size())
        o += "      std: {position: " + vec(result_->std.marker_position[m]) + "}\n";
      if (m < result_->marker_residual.size())
        o += residualLine("      ", result_->marker_residual[m]);
    }
  }

  // `column:` only where it is not the name, so that a seed reads as it was.
  static void column(std::string& o, const std::string& name, const std::string& column) {
    if (!column.empty() && column != name) o += "    column: " + scalar(column) + "\n";
  }

  static void gainBias(std::string& o, const GainBias& gb, double sigma,
                       const FixedGainBias& fixed) {
    o += "    gain: " + num(gb.gain) + "\n";
    o += "    bias: " + num(gb.bias) + "\n";
    o += "    sigma: " + num(sigma) + "\n";
    o += "    fixed: " + fixedValue(fixed.gain, fixed.bias, "gain", "bias") + "\n";
  }

  static void tendonPath(std::string& o, const TendonSensorConfig& c) {
    o += "    path:\n";
    for (const PathAnchor& a : c.path)
      o += "      - {link: " + scalar(a.link_name) + ", point: " + vec(a.point) + "}\n";
  }

  static void tendonCoupling(std::string& o, const TendonSensorConfig& c) {
    o += "    coupling: {";
    for (size_t k = 0; k < c.coupling.size(); ++k)
      o += (k ? ", " : "") + scalar(c.coupling[k].joint_name) + ": " +
           num(c.coupling[k].coefficient);
    o += "}\n";
  }

  // A sensor's std and residual lines, where the calibration has them.
  static void extras(std::string& o, const std::vector<GainBias>& std_of,
                     const std::vector<ResidualStats>& res, size_t i) {
    if (i < std_of.size())
      o += "    std: {gain: " + num(std_of[i].gain) + ", bias: " + num(std_of[i].bias) + "}\n";
    if (i < res.size()) o += residualLine("    ", res[i]);
  }

  const SensorSet& s_;
  const SensorParameters& th_;
  const CalibrationResult* result_;
  const SensorSet& sig_;
};

// SPEC §3 "Kinematic calibration: joint origins", with std per joint in a
// calibration output.
void jointOrigins(std::string& o, const SensorSet& s, const SensorParameters& th,
                  const CalibrationResult* result) {
  o += "joint_origins:\n";
  const OriginPrior& p = s.origin_prior;
  if (p.any()) {
    o += "  prior_std: {";
    if (p.xyz > 0) o += "xyz: " + num(p.xyz) + (p.rpy > 0 ? ", " : "");
    if (p.rpy > 0) o += "rpy: " + num(p.rpy);
    o += "}\n";
  }
  o += "  joints:\n";
  for (size_t c = 0; c < s.joint_origins.size(); ++c) {
    const JointOriginConfig& jc = s.joint_origins[c];
    o += "    - joint: " + scalar(jc.joint_name) + "\n";
    o += "      xyz: " + vec(th.joint_origin[c].xyz) + "\n";
    o += "      rpy: " + vec(th.joint_origin[c].rpy) + "\n";
    o += "      fixed: " + fixedValue(jc.fixed.xyz, jc.fixed.rpy, "xyz", "rpy") + "\n";
    if (result && c < result->std.joint_origin.size())
      o += "      std: {xyz: " + vec(result->std.joint_origin[c].xyz) +
           ", rpy: " + vec(result->std.joint_origin[c].rpy) + "}\n";
  }
}

void originDetermination(std::string& o, const std::vector<OriginDetermination>& origins) {
  if (origins.empty()) return;
  o += "  joint_origins:\n";
  for (const OriginDetermination& d : origins)
    o += "    - {joint: " + scalar(d.joint) + ", determined: " + list(d.determined) +
         ", on_prior: " + list(d.on_prior) + "}\n";
}

// An empty list as "[]" so that it reads back as a list, not as null.
void unidentifiable(std::string& o, const std::vector<UnidentifiableDirection>& list) {
  if (list.empty()) {
    o += "  unidentifiable: []\n";
    return;
  }
  o += "  unidentifiable:\n";
  for (const UnidentifiableDirection& d : list) {
    o += "    - parameters: [";
    for (size_t k = 0; k < d.parameters.size(); ++k)
      o += (k ? ", " : "") + quoted(d.parameters[k]);
    o += "]\n      reason: " + quoted(d.reason) + "\n";
    o += "      kind: " + std::string(undeterminedName(d.kind)) + "\n";
  }
}

void downweighted(std::string& o, const std::vector<DownweightedReading>& list) {
  if (list.empty()) {
    o += "  downweighted: []\n";
    return;
  }
  o += "  downweighted:\n";
  for (const DownweightedReading& d : list)
    o += "    - {frame: " + std::to_string(d.frame) + ", sensor: " + quoted(d.sensor) +
         ", weight: " + num(d.weight) + "}\n";
}

void summary(std::string& o, const CalibrationSummary& sm) {
  o += "summary:\n";
  o += "  method: " + scalar(sm.method.empty() ? "unknown" : sm.method) + "\n";
  if (!sm.q_phase.empty()) o += "  q_phase: " + scalar(sm.q_phase) + "\n";
  o += "  iterations: " + std::to_string(sm.iterations) + "\n";
  o += "  converged: " + std::string(boolean(sm.converged)) + "\n";
  o += "  initial_cost: " + num(sm.initial_cost) + "\n";
  o += "  final_cost: " + num(sm.final_cost) + "\n";
  o += "  frames: " + std::to_string(sm.frames) + "\n";
  o += "  wall_time: " + num(sm.wall_time) + "\n";
  o += "  sigma: " + perGroup(sm, sm.group_sigma) + "\n";
  o += "  rms_before: " + perGroup(sm, sm.before_rms) + "\n";
  o += "  rms_after: " + perGroup(sm, sm.after_rms) + "\n";
  unidentifiable(o, sm.unidentifiable);
  originDetermination(o, sm.origins);
  downweighted(o, sm.downweighted);
  const int* spikes = sm.spikes_set_aside;
  o += "  spikes_set_aside: {marker: " + std::to_string(spikes[0]) +
       ", joint: " + std::to_string(spikes[1]) + ", tendon: " + std::to_string(spikes[2]) + "}\n";
  if (sm.verdict.empty()) {
    o += "  verdict: ok\n";
    return;
  }
  o += "  verdict:\n";
  for (const std::string& reason : sm.verdict) o += "    - " + quoted(reason) + "\n";
}

}  // namespace

std::string sensorsToYaml(const SensorSet& s, const SensorParameters& th,
                          const CalibrationResult* result) {
  const Writer w(s, th, result);
  std::string o;
  if (result) o += "# Calibration written by stac_calib; feed it back with --sensors.\n";
  // Empty sections are left out: the reader takes a missing one as empty.
  if (!s.markers.empty()) w.mocap(o);
  if (!s.joint_sensors.empty()) w.jointSensors(o);
  if (!s.tendon_sensors.empty()) w.tendonSensors(o);
  if (!s.joint_origins.empty()) jointOrigins(o, s, th, result);
  if (!s.ignore_columns.empty()) o += "ignore_columns: " + list(s.ignore_columns) + "\n";
  if (result) summary(o, result->summary);
  return o;
}

}  // namespace stac
