// The sensors file (SPEC §3): a strict reader on yaml-cpp (every error names
// the file, the line and the key) and a hand-written writer whose numbers
// both YAML 1.1 and 1.2 readers take as floats and which round-trips exactly.
#include "stac/sensors_file.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <sstream>

#include "stac/error.hpp"
#include "stac/file_io.hpp"

namespace stac {
namespace {

class Reader {
 public:
  Reader(std::string file, const RobotModel& robot) : file_(std::move(file)), robot_(robot) {}

  [[noreturn]] void fail(const YAML::Node& at, const std::string& key, const std::string& what) const {
    const int line = at.Mark().line >= 0 ? at.Mark().line + 1 : 0;
    throw InputError(file_, line, 0, "key '" + key + "': " + what);
  }

  // Checks a mapping: only `allowed` keys, none twice. Returns key -> value.
  std::map<std::string, YAML::Node> fields(const YAML::Node& node, const std::string& key,
                                           const std::set<std::string>& allowed) const {
    if (!node.IsMap()) fail(node, key, "expected a mapping");
    std::map<std::string, YAML::Node> out;
    for (auto it = node.begin(); it != node.end(); ++it) {
      if (!it->first.IsScalar()) fail(it->first, key, "a key must be a plain name");
      const std::string k = it->first.Scalar();
      const std::string path = key.empty() ? k : key + "." + k;
      if (!allowed.count(k)) {
        std::string list;
        for (const std::string& a : allowed) list += (list.empty() ? "" : ", ") + a;
        fail(it->first, path, "unknown key (expected one of: " + list + ")");
      }
      if (out.count(k)) fail(it->first, path, "given twice");
      out.emplace(k, it->second);
    }
    return out;
  }

  double number(const YAML::Node& n, const std::string& key) const {
    if (!n.IsScalar()) fail(n, key, "expected a number");
    const std::string& s = n.Scalar();
    double v = 0;
    try {
      v = n.as<double>();
    } catch (const YAML::Exception&) {
      fail(n, key, "expected a number, got '" + s + "'");
    }
    if (!std::isfinite(v)) fail(n, key, "'" + s + "' is not a finite number");
    return v;
  }

  double sigma(const YAML::Node& n, const std::string& key) const {
    const double v = number(n, key);
    if (!(v > 0)) fail(n, key, "a sigma must be positive and finite");
    return v;
  }

  bool boolean(const YAML::Node& n, const std::string& key) const {
    if (!n.IsScalar()) fail(n, key, "expected true or false");
    const std::string& s = n.Scalar();
    if (s == "true" || s == "True" || s == "TRUE") return true;
    if (s == "false" || s == "False" || s == "FALSE") return false;
    fail(n, key, "expected true or false, got '" + s + "'");
  }

  std::string text(const YAML::Node& n, const std::string& key) const {
    if (!n.IsScalar() || n.Scalar().empty()) fail(n, key, "expected a name");
    return n.Scalar();
  }

  Eigen::VectorXd vector(const YAML::Node& n, const std::string& key, int size) const {
    if (!n.IsSequence() || static_cast<int>(n.size()) != size)
      fail(n, key, "expected a list of " + std::to_string(size) + " numbers");
    Eigen::VectorXd v(size);
    for (int i = 0; i < size; ++i) v[i] = number(n[i], key + "[" + std::to_string(i) + "]");
    return v;
  }

  int link(const YAML::Node& n, const std::string& key) const {
    const std::string name = text(n, key);
    const auto idx = robot_.linkIndex(name);
    if (!idx) fail(n, key, "unknown link '" + name + "' (not in " + robot_.sourceName() + ")");
    return *idx;
  }

  int joint(const YAML::Node& n, const std::string& key) const {
    const std::string name = text(n, key);
    const auto idx = robot_.movableJointIndex(name);
    if (!idx) {
      const bool exists = std::count(robot_.allJointNames().begin(), robot_.allJointNames().end(), name);
      fail(n, key, exists ? "joint '" + name + "' is fixed: it has no angle to sense"
                          : "unknown joint '" + name + "' (not in " + robot_.sourceName() + ")");
    }
    return *idx;
  }

  // Every name becomes log column(s): they must not collide.
  void claimName(const YAML::Node& at, const std::string& key, const std::string& name,
                 bool marker) {
    std::vector<std::string> cols;
    if (marker) cols = {name + ".x", name + ".y", name + ".z"};
    else cols = {name};
    if (!names_.insert(name).second) fail(at, key, "name '" + name + "' is used twice");
    for (const std::string& c : cols)
      if (!columns_.insert(c).second)
        fail(at, key, "name '" + name + "' gives log column '" + c + "', which another sensor has");
  }

  const std::string& file() const { return file_; }

 private:
  std::string file_;
  const RobotModel& robot_;
  std::set<std::string> names_, columns_;
};

Eigen::Quaterniond fromRpy(const Eigen::Vector3d& rpy) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(rpy[2], Eigen::Vector3d::UnitZ()) *
                            Eigen::AngleAxisd(rpy[1], Eigen::Vector3d::UnitY()) *
                            Eigen::AngleAxisd(rpy[0], Eigen::Vector3d::UnitX()));
}

// URDF roll-pitch-yaw of R = Rz(yaw) Ry(pitch) Rx(roll).
Eigen::Vector3d toRpy(const Eigen::Matrix3d& R) {
  const double sp = std::clamp(-R(2, 0), -1.0, 1.0);
  const double pitch = std::asin(sp);
  if (std::abs(sp) > 1.0 - 1e-12) {
    // Gimbal lock: only roll ± yaw is defined; put it all in yaw.
    return Eigen::Vector3d(0.0, pitch, std::atan2(-R(0, 1), R(1, 1)));
  }
  return Eigen::Vector3d(std::atan2(R(2, 1), R(2, 2)), pitch, std::atan2(R(1, 0), R(0, 0)));
}

void readFrame(Reader& rd, const YAML::Node& node, SensorSet* s, SensorParameters* th) {
  auto f = rd.fields(node, "mocap.frame", {"translation", "rpy", "quaternion", "fixed", "std"});
  if (f.count("translation")) th->mocap.translation = rd.vector(f["translation"], "mocap.frame.translation", 3);
  if (f.count("fixed")) s->mocap_frame_fixed = rd.boolean(f["fixed"], "mocap.frame.fixed");
  std::optional<Eigen::Quaterniond> from_q, from_rpy;
  if (f.count("quaternion")) {
    const Eigen::Vector4d q = rd.vector(f["quaternion"], "mocap.frame.quaternion", 4);
    if (q.norm() < 1e-9) rd.fail(f["quaternion"], "mocap.frame.quaternion", "a zero quaternion is no rotation");
    from_q = Eigen::Quaterniond(q[0], q[1], q[2], q[3]).normalized();
  }
  if (f.count("rpy")) from_rpy = fromRpy(rd.vector(f["rpy"], "mocap.frame.rpy", 3));
  if (from_q && from_rpy && from_q->angularDistance(*from_rpy) > 1e-6)
    rd.fail(f["rpy"], "mocap.frame.rpy",
            "rpy and quaternion disagree (by " + std::to_string(from_q->angularDistance(*from_rpy)) +
                " rad); give one of them");
  if (from_q) th->mocap.rotation = *from_q;
  else if (from_rpy) th->mocap.rotation = *from_rpy;
}

void readMocap(Reader& rd, const YAML::Node& node, SensorSet* s, SensorParameters* th) {
  auto f = rd.fields(node, "mocap", {"sigma", "frame", "markers"});
  if (f.count("sigma")) s->mocap_sigma = rd.sigma(f["sigma"], "mocap.sigma");
  if (f.count("frame")) readFrame(rd, f["frame"], s, th);
  if (!f.count("markers")) return;
  const YAML::Node& list = f["markers"];
  if (list.IsNull()) return;
  if (!list.IsSequence()) rd.fail(list, "mocap.markers", "expected a list of markers");
  // σ of markers without their own: mocap.sigma, known once the section is read.
  for (size_t i = 0; i < list.size(); ++i) {
    const std::string key = "mocap.markers[" + std::to_string(i) + "]";
    auto m = rd.fields(list[i], key, {"name", "link", "position", "fixed", "sigma", "std", "residual"});
    MarkerConfig mc;
    if (!m.count("name")) rd.fail(list[i], key + ".name", "missing");
    if (!m.count("link")) rd.fail(list[i], key + ".link", "missing");
    mc.name = rd.text(m["name"], key + ".name");
    rd.claimName(m["name"], key + ".name", mc.name, true);
    mc.link = rd.link(m["link"], key + ".link");
    mc.link_name = m["link"].Scalar();
    Eigen::Vector3d d = Eigen::Vector3d::Zero();
    if (m.count("position")) d = rd.vector(m["position"], key + ".position", 3);
    if (m.count("fixed")) mc.fixed = rd.boolean(m["fixed"], key + ".fixed");
    mc.sigma = s->mocap_sigma;
    if (m.count("sigma")) {
      mc.sigma = rd.sigma(m["sigma"], key + ".sigma");
      mc.sigma_overridden = true;
    }
    s->markers.push_back(mc);
    th->marker_position.push_back(d);
  }
}

void readGainBias(Reader& rd, std::map<std::string, YAML::Node>& f, const std::string& key,
                  double* sigma, bool* fixed, GainBias* gb) {
  if (f.count("gain")) gb->gain = rd.number(f["gain"], key + ".gain");
  if (f.count("bias")) gb->bias = rd.number(f["bias"], key + ".bias");
  if (f.count("sigma")) *sigma = rd.sigma(f["sigma"], key + ".sigma");
  if (f.count("fixed")) *fixed = rd.boolean(f["fixed"], key + ".fixed");
}

void readJointSensors(Reader& rd, const YAML::Node& list, SensorSet* s, SensorParameters* th) {
  if (list.IsNull()) return;
  if (!list.IsSequence()) rd.fail(list, "joint_sensors", "expected a list of sensors");
  for (size_t i = 0; i < list.size(); ++i) {
    const std::string key = "joint_sensors[" + std::to_string(i) + "]";
    auto f = rd.fields(list[i], key,
                       {"name", "joint", "gain", "bias", "sigma", "fixed", "std", "residual"});
    if (!f.count("name")) rd.fail(list[i], key + ".name", "missing");
    if (!f.count("joint")) rd.fail(list[i], key + ".joint", "missing");
    JointSensorConfig c;
    c.name = rd.text(f["name"], key + ".name");
    rd.claimName(f["name"], key + ".name", c.name, false);
    c.joint = rd.joint(f["joint"], key + ".joint");
    c.joint_name = f["joint"].Scalar();
    GainBias gb;
    readGainBias(rd, f, key, &c.sigma, &c.fixed, &gb);
    s->joint_sensors.push_back(c);
    th->joint_sensor.push_back(gb);
  }
}

void readTendonSensors(Reader& rd, const YAML::Node& list, SensorSet* s, SensorParameters* th) {
  if (list.IsNull()) return;
  if (!list.IsSequence()) rd.fail(list, "tendon_sensors", "expected a list of sensors");
  for (size_t i = 0; i < list.size(); ++i) {
    const std::string key = "tendon_sensors[" + std::to_string(i) + "]";
    auto f = rd.fields(list[i], key, {"name", "gain", "bias", "sigma", "fixed", "path",
                                      "coupling", "std", "residual"});
    if (!f.count("name")) rd.fail(list[i], key + ".name", "missing");
    TendonSensorConfig c;
    c.name = rd.text(f["name"], key + ".name");
    rd.claimName(f["name"], key + ".name", c.name, false);
    GainBias gb;
    readGainBias(rd, f, key, &c.sigma, &c.fixed, &gb);
    const bool has_path = f.count("path") > 0, has_coupling = f.count("coupling") > 0;
    if (has_path == has_coupling)
      rd.fail(list[i], key, has_path ? "give either path or coupling, not both"
                                     : "needs a path or a coupling");
    if (has_path) {
      const YAML::Node& p = f["path"];
      if (!p.IsSequence()) rd.fail(p, key + ".path", "expected a list of {link, point}");
      if (p.size() < 2) rd.fail(p, key + ".path", "a path needs at least two points");
      for (size_t k = 0; k < p.size(); ++k) {
        const std::string pk = key + ".path[" + std::to_string(k) + "]";
        auto a = rd.fields(p[k], pk, {"link", "point"});
        if (!a.count("link")) rd.fail(p[k], pk + ".link", "missing");
        if (!a.count("point")) rd.fail(p[k], pk + ".point", "missing");
        PathAnchor anchor;
        anchor.link = rd.link(a["link"], pk + ".link");
        anchor.link_name = a["link"].Scalar();
        anchor.point = rd.vector(a["point"], pk + ".point", 3);
        c.path.push_back(anchor);
      }
    } else {
      c.kind = TendonSensorConfig::Kind::kCoupling;
      const YAML::Node& cp = f["coupling"];
      if (!cp.IsMap() || cp.size() == 0)
        rd.fail(cp, key + ".coupling", "expected a mapping of joint: coefficient");
      std::set<std::string> seen;
      for (auto it = cp.begin(); it != cp.end(); ++it) {
        const std::string ck = key + ".coupling." + it->first.Scalar();
        if (!seen.insert(it->first.Scalar()).second) rd.fail(it->first, ck, "given twice");
        CouplingTerm term;
        term.joint = rd.joint(it->first, ck);
        term.joint_name = it->first.Scalar();
        term.coefficient = rd.number(it->second, ck);
        c.coupling.push_back(term);
      }
    }
    s->tendon_sensors.push_back(c);
    th->tendon_sensor.push_back(gb);
  }
}

// ---- writing ----

std::string num(double v) { return formatNumber(v); }

std::string vec(const Eigen::Ref<const Eigen::VectorXd>& v) {
  std::string s = "[";
  for (Eigen::Index i = 0; i < v.size(); ++i) s += (i ? ", " : "") + num(v[i]);
  return s + "]";
}

// A YAML double-quoted string.
std::string quoted(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    if (c == '\n') {
      out += "\\n";
      continue;
    }
    out += c;
  }
  return out + "\"";
}

// A plain scalar if it is safe as one, else quoted.
std::string name(const std::string& s) {
  const bool plain = !s.empty() &&
                     std::all_of(s.begin(), s.end(), [](char c) {
                       return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.' ||
                              c == '-' || c == '/';
                     }) &&
                     !std::isdigit(static_cast<unsigned char>(s[0])) && s[0] != '-' && s[0] != '.' &&
                     s != "true" && s != "false" && s != "null" && s != "yes" && s != "no" &&
                     s != "on" && s != "off" && s != "y" && s != "n";
  return plain ? s : quoted(s);
}

void residualLine(std::ostringstream& o, const std::string& indent, const ResidualStats& r) {
  o << indent << "residual: {rms: " << num(r.rms) << ", mae: " << num(r.mae)
    << ", count: " << r.count << "}\n";
}

}  // namespace

SensorsFile parseSensorsYaml(const std::string& text, const std::string& source_name,
                             const RobotModel& model) {
  Reader rd(source_name, model);
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::ParserException& e) {
    throw InputError(source_name, e.mark.line + 1, e.mark.column + 1, "malformed YAML: " + e.msg);
  }
  SensorsFile out;
  if (root.IsNull()) throw InputError(source_name, "the sensors file is empty: no sensors");
  auto f = rd.fields(root, "", {"mocap", "joint_sensors", "tendon_sensors", "summary"});
  if (f.count("mocap")) readMocap(rd, f["mocap"], &out.sensors, &out.theta);
  if (f.count("joint_sensors")) readJointSensors(rd, f["joint_sensors"], &out.sensors, &out.theta);
  if (f.count("tendon_sensors")) readTendonSensors(rd, f["tendon_sensors"], &out.sensors, &out.theta);
  if (out.sensors.markers.empty() && out.sensors.joint_sensors.empty() &&
      out.sensors.tendon_sensors.empty())
    throw InputError(source_name, "no sensors: give mocap.markers, joint_sensors or tendon_sensors");
  return out;
}

SensorsFile loadSensorsFile(const std::string& path, const RobotModel& model) {
  return parseSensorsYaml(readTextFile(path), path, model);
}

std::string sensorsToYaml(const SensorSet& s, const SensorParameters& th,
                          const CalibrationResult* result) {
  std::ostringstream o;
  if (result) o << "# Calibration written by stac_calib; feed it back with --sensors.\n";
  if (!s.markers.empty()) {
    o << "mocap:\n";
    o << "  sigma: " << num(s.mocap_sigma) << "\n";
    o << "  frame:\n";
    o << "    translation: " << vec(th.mocap.translation) << "\n";
    const Eigen::Quaterniond q = th.mocap.rotation.normalized();
    o << "    rpy: " << vec(toRpy(q.toRotationMatrix())) << "\n";
    o << "    quaternion: " << vec(Eigen::Vector4d(q.w(), q.x(), q.y(), q.z())) << "\n";
    o << "    fixed: " << (s.mocap_frame_fixed ? "true" : "false") << "\n";
    if (result)
      o << "    std: {translation: " << vec(result->std.mocap_translation)
        << ", rotation: " << vec(result->std.mocap_rotation) << "}\n";
    o << "  markers:\n";
    for (size_t m = 0; m < s.markers.size(); ++m) {
      const MarkerConfig& mc = s.markers[m];
      o << "    - name: " << name(mc.name) << "\n";
      o << "      link: " << name(mc.link_name) << "\n";
      o << "      position: " << vec(th.marker_position[m]) << "\n";
      o << "      fixed: " << (mc.fixed ? "true" : "false") << "\n";
      if (mc.sigma_overridden || mc.sigma != s.mocap_sigma) o << "      sigma: " << num(mc.sigma) << "\n";
      if (result) {
        o << "      std: {position: " << vec(result->std.marker_position[m]) << "}\n";
        residualLine(o, "      ", result->marker_residual[m]);
      }
    }
  }
  auto gainBias = [&](const std::string& indent, const GainBias& gb, double sigma, bool fixed) {
    o << indent << "gain: " << num(gb.gain) << "\n";
    o << indent << "bias: " << num(gb.bias) << "\n";
    o << indent << "sigma: " << num(sigma) << "\n";
    o << indent << "fixed: " << (fixed ? "true" : "false") << "\n";
  };
  if (!s.joint_sensors.empty()) {
    o << "joint_sensors:\n";
    for (size_t j = 0; j < s.joint_sensors.size(); ++j) {
      const JointSensorConfig& c = s.joint_sensors[j];
      o << "  - name: " << name(c.name) << "\n";
      o << "    joint: " << name(c.joint_name) << "\n";
      gainBias("    ", th.joint_sensor[j], c.sigma, c.fixed);
      if (result) {
        o << "    std: {gain: " << num(result->std.joint_sensor[j].gain)
          << ", bias: " << num(result->std.joint_sensor[j].bias) << "}\n";
        residualLine(o, "    ", result->joint_residual[j]);
      }
    }
  }
  if (!s.tendon_sensors.empty()) {
    o << "tendon_sensors:\n";
    for (size_t j = 0; j < s.tendon_sensors.size(); ++j) {
      const TendonSensorConfig& c = s.tendon_sensors[j];
      o << "  - name: " << name(c.name) << "\n";
      gainBias("    ", th.tendon_sensor[j], c.sigma, c.fixed);
      if (c.kind == TendonSensorConfig::Kind::kPath) {
        o << "    path:\n";
        for (const PathAnchor& a : c.path)
          o << "      - {link: " << name(a.link_name) << ", point: " << vec(a.point) << "}\n";
      } else {
        o << "    coupling: {";
        for (size_t k = 0; k < c.coupling.size(); ++k)
          o << (k ? ", " : "") << name(c.coupling[k].joint_name) << ": "
            << num(c.coupling[k].coefficient);
        o << "}\n";
      }
      if (result) {
        o << "    std: {gain: " << num(result->std.tendon_sensor[j].gain)
          << ", bias: " << num(result->std.tendon_sensor[j].bias) << "}\n";
        residualLine(o, "    ", result->tendon_residual[j]);
      }
    }
  }
  if (result) {
    const CalibrationSummary& sm = result->summary;
    o << "summary:\n";
    o << "  method: " << name(sm.method) << "\n";
    if (!sm.q_phase.empty()) o << "  q_phase: " << name(sm.q_phase) << "\n";
    o << "  iterations: " << sm.iterations << "\n";
    o << "  converged: " << (sm.converged ? "true" : "false") << "\n";
    o << "  initial_cost: " << num(sm.initial_cost) << "\n";
    o << "  final_cost: " << num(sm.final_cost) << "\n";
    o << "  frames: " << sm.frames << "\n";
    o << "  wall_time: " << num(sm.wall_time) << "\n";
    o << "  sigma: {";
    bool first = true;
    for (int g = 0; g < kNumSensorGroups; ++g) {
      if (!sm.group_present[g]) continue;
      o << (first ? "" : ", ") << groupName(static_cast<SensorGroup>(g)) << ": "
        << num(sm.group_sigma[g]);
      first = false;
    }
    o << "}\n";
    o << "  rms_before: {";
    first = true;
    for (int g = 0; g < kNumSensorGroups; ++g) {
      if (!sm.group_present[g]) continue;
      o << (first ? "" : ", ") << groupName(static_cast<SensorGroup>(g)) << ": "
        << num(sm.before_rms[g]);
      first = false;
    }
    o << "}\n  rms_after: {";
    first = true;
    for (int g = 0; g < kNumSensorGroups; ++g) {
      if (!sm.group_present[g]) continue;
      o << (first ? "" : ", ") << groupName(static_cast<SensorGroup>(g)) << ": "
        << num(sm.after_rms[g]);
      first = false;
    }
    o << "}\n";
    if (sm.unidentifiable.empty()) {
      o << "  unidentifiable: []\n";
    } else {
      o << "  unidentifiable:\n";
      for (const UnidentifiableDirection& d : sm.unidentifiable) {
        o << "    - parameters: [";
        for (size_t k = 0; k < d.parameters.size(); ++k) o << (k ? ", " : "") << quoted(d.parameters[k]);
        o << "]\n      reason: " << quoted(d.reason) << "\n";
      }
    }
    if (!sm.downweighted.empty()) {
      o << "  downweighted:\n";
      for (const DownweightedReading& d : sm.downweighted)
        o << "    - {frame: " << d.frame << ", sensor: " << quoted(d.sensor)
          << ", weight: " << num(d.weight) << "}\n";
    }
  }
  return o.str();
}

namespace {

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

}  // namespace

SensorsFile inferSensorsFromLog(const Log& log, const RobotModel& model) {
  SensorsFile out;
  out.sensors.mocap_sigma = 0.002;
  std::set<std::string> columns(log.columns.begin(), log.columns.end());
  std::set<std::string> placed;
  std::vector<std::string> candidates;
  for (const MovableJoint& j : model.movableJoints()) candidates.push_back(j.name);
  for (const Link& l : model.links()) candidates.push_back(l.name);
  for (const std::string& c : log.columns) {
    if (placed.count(c)) continue;
    if (auto j = model.movableJointIndex(c)) {
      JointSensorConfig s;
      s.name = c;
      s.joint_name = c;
      s.joint = *j;
      s.sigma = 0.01;
      out.sensors.joint_sensors.push_back(s);
      out.theta.joint_sensor.push_back({1.0, 0.0});
      placed.insert(c);
      continue;
    }
    const auto dot = c.rfind('.');
    if (dot == std::string::npos) continue;
    const std::string base = c.substr(0, dot), axis = c.substr(dot + 1);
    if (axis != "x" && axis != "y" && axis != "z") continue;
    const auto link = model.linkIndex(base);
    if (!link) continue;
    if (!columns.count(base + ".x") || !columns.count(base + ".y") || !columns.count(base + ".z"))
      continue;
    MarkerConfig m;
    m.name = base;
    m.link_name = base;
    m.link = *link;
    m.sigma = 0.002;
    out.sensors.markers.push_back(m);
    out.theta.marker_position.push_back(Eigen::Vector3d::Zero());
    placed.insert(base + ".x");
    placed.insert(base + ".y");
    placed.insert(base + ".z");
  }
  std::string unplaced;
  int count = 0;
  for (const std::string& c : log.columns) {
    if (placed.count(c)) continue;
    std::string key = c;
    const auto dot = c.rfind('.');
    if (dot != std::string::npos) {
      const std::string axis = c.substr(dot + 1);
      if (axis == "x" || axis == "y" || axis == "z") key = c.substr(0, dot);
    }
    std::string best;
    size_t best_d = std::string::npos;
    for (const std::string& cand : candidates) {
      const size_t d = editDistance(key, cand);
      if (d < best_d) best_d = d, best = cand;
    }
    std::string hint;
    if (model.linkIndex(key) && key != c)
      hint = "a marker needs all of " + key + ".x, " + key + ".y and " + key + ".z";
    else
      hint = "closest joint or link: '" + best + "'";
    unplaced += "\n  " + c + " (" + hint + ")";
    ++count;
  }
  if (count > 0)
    throw InputError(log.path, log.header_line, 0,
                     std::to_string(count) + " column(s) name no movable joint and no link, so "
                     "no sensor could be inferred for them (give --sensors):" + unplaced);
  if (out.sensors.joint_sensors.empty() && out.sensors.markers.empty())
    throw InputError(log.path, log.header_line, 0, "the log has no sensor columns");
  return out;
}

}  // namespace stac
