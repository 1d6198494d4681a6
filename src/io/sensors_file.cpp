// The sensors file (SPEC §3): a strict reader on yaml-cpp (every error names
// the file, the line and the key) and a hand-written writer whose numbers
// both YAML 1.1 and 1.2 readers take as floats and which round-trips exactly.
#include "stac/sensors_file.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cassert>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <string_view>

#include "stac/error.hpp"
#include "stac/file_io.hpp"

namespace stac {
namespace {

// ---- rotations ----

// URDF convention: R = Rz(yaw) Ry(pitch) Rx(roll).
Eigen::Quaterniond fromRpy(const Eigen::Vector3d& rpy) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(rpy[2], Eigen::Vector3d::UnitZ()) *
                            Eigen::AngleAxisd(rpy[1], Eigen::Vector3d::UnitY()) *
                            Eigen::AngleAxisd(rpy[0], Eigen::Vector3d::UnitX()));
}

// The roll-pitch-yaw of a rotation, accurate to ~1e-8 rad everywhere. Away
// from gimbal lock the usual atan2 formulas; as |cos(pitch)| -> 0 roll and
// yaw lose their meaning (only yaw ∓ roll is defined) and their atan2
// arguments shrink to rounding noise, so near the lock the decomposition
// with roll = 0 is also tried and the better of the two kept.
Eigen::Vector3d toRpy(const Eigen::Quaterniond& q) {
  const Eigen::Matrix3d R = q.toRotationMatrix();
  const double c = std::hypot(R(0, 0), R(1, 0));  // cos(pitch) >= 0
  const double pitch = std::atan2(-R(2, 0), c);
  const Eigen::Vector3d regular(std::atan2(R(2, 1), R(2, 2)), pitch, std::atan2(R(1, 0), R(0, 0)));
  if (c > 1e-4) return regular;
  // R01 = -sin(yaw ∓ roll), R11 = cos(yaw ∓ roll) when cos(pitch) = 0.
  const Eigen::Vector3d locked(0.0, pitch, std::atan2(-R(0, 1), R(1, 1)));
  return fromRpy(regular).angularDistance(q) <= fromRpy(locked).angularDistance(q) ? regular
                                                                                   : locked;
}

// A unit quaternion: unchanged if it already is one to rounding (so that
// writing and reading it back is exact), else normalized.
Eigen::Quaterniond unitQuaternion(const Eigen::Quaterniond& q) {
  if (std::abs(q.squaredNorm() - 1.0) <= 1e-14) return q;
  return q.normalized();
}

// ---- reading ----

// A YAML plain scalar as a double: decimal and exponent forms of YAML 1.1
// and 1.2 ("1", "1.0", "1e-05", "1.0e-05", "+2."), and .inf/.nan.
std::optional<double> parseNumber(const std::string& s) {
  std::string_view v(s);
  bool negative = false;
  if (!v.empty() && (v.front() == '+' || v.front() == '-')) {
    negative = v.front() == '-';
    v.remove_prefix(1);
  }
  if (v == ".inf" || v == ".Inf" || v == ".INF")
    return negative ? -std::numeric_limits<double>::infinity()
                    : std::numeric_limits<double>::infinity();
  if (v == ".nan" || v == ".NaN" || v == ".NAN") return std::numeric_limits<double>::quiet_NaN();
  if (v.empty() || !(std::isdigit(static_cast<unsigned char>(v.front())) || v.front() == '.'))
    return std::nullopt;
  double x = 0;
  const auto res = std::from_chars(v.data(), v.data() + v.size(), x);
  if (res.ptr != v.data() + v.size()) return std::nullopt;
  if (res.ec == std::errc::result_out_of_range)  // underflow -> 0 or subnormal, overflow -> inf
    x = std::strtod(std::string(v).c_str(), nullptr);
  else if (res.ec != std::errc())
    return std::nullopt;
  return negative ? -x : x;
}

bool isTimeName(const std::string& s) { return s == "time" || s == "t" || s == "timestamp"; }

class Reader {
 public:
  Reader(std::string file, const RobotModel& robot) : file_(std::move(file)), robot_(robot) {}

  [[noreturn]] void fail(const YAML::Node& at, const std::string& key,
                         const std::string& what) const {
    const int line = at.Mark().line >= 0 ? at.Mark().line + 1 : 0;
    throw InputError(file_, line, 0, "key '" + key + "': " + what);
  }

  // Checks a mapping: only `allowed` keys, none twice (yaml-cpp keeps both
  // entries of a duplicated key, so they are seen here). Returns key -> value.
  std::map<std::string, YAML::Node> fields(const YAML::Node& node, const std::string& key,
                                           const std::set<std::string>& allowed) const {
    if (!node.IsMap()) {
      std::string list;
      for (const std::string& a : allowed) list += (list.empty() ? "" : ", ") + a;
      fail(node, key, "expected a mapping (with keys among: " + list + ")");
    }
    static const std::set<std::string> kMayBeEmpty = {
        "mocap", "frame", "markers", "joint_sensors", "tendon_sensors", "summary", "std", "residual"};
    std::map<std::string, YAML::Node> out;
    std::map<std::string, int> lines;
    for (auto it = node.begin(); it != node.end(); ++it) {
      if (!it->first.IsScalar()) fail(it->first, key, "a key must be a plain name");
      const std::string k = it->first.Scalar();
      const std::string path = key == kTop ? k : key + "." + k;
      if (!allowed.count(k)) {
        std::string list;
        for (const std::string& a : allowed) list += (list.empty() ? "" : ", ") + a;
        fail(it->first, path, "unknown key (expected one of: " + list + ")");
      }
      if (out.count(k))
        fail(it->first, path, "given twice (first on line " + std::to_string(lines[k]) + ")");
      // An empty value is an empty section, or else an error reported on
      // the key's line (yaml-cpp marks an empty value at the next token).
      if (it->second.IsNull() && !kMayBeEmpty.count(k))
        fail(it->first, path, "expected a value, got nothing");
      out.emplace(k, it->second);
      lines[k] = it->first.Mark().line + 1;
    }
    return out;
  }

  double number(const YAML::Node& n, const std::string& key) const {
    if (!n.IsScalar()) fail(n, key, n.IsNull() ? "expected a number, got nothing" : "expected a number");
    const std::string& s = n.Scalar();
    if (n.Tag() == "!") fail(n, key, "expected a number, got the quoted string \"" + s + "\"");
    const std::optional<double> v = parseNumber(s);
    if (!v) fail(n, key, "expected a number, got '" + s + "'");
    if (!std::isfinite(*v)) fail(n, key, "'" + s + "' is not a finite number");
    return *v;
  }

  double sigma(const YAML::Node& n, const std::string& key) const {
    const double v = number(n, key);
    if (!(v > 0)) fail(n, key, "a sigma must be positive and finite, got " + n.Scalar());
    return v;
  }

  bool boolean(const YAML::Node& n, const std::string& key) const {
    if (!n.IsScalar() || n.Tag() == "!") fail(n, key, "expected true or false");
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
    if (!n.IsSequence())
      fail(n, key, "expected a list of " + std::to_string(size) + " numbers");
    if (static_cast<int>(n.size()) != size)
      fail(n, key,
           "expected a list of " + std::to_string(size) + " numbers, got " +
               std::to_string(n.size()));
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
      const auto& all = robot_.allJointNames();
      const bool exists = std::find(all.begin(), all.end(), name) != all.end();
      fail(n, key, exists ? "joint '" + name + "' is fixed: it has no angle to sense"
                          : "unknown joint '" + name + "' (not in " + robot_.sourceName() + ")");
    }
    return *idx;
  }

  // A sensor's or marker's name; names become log columns (a marker's with
  // .x/.y/.z), so no two may collide and none may read as the time column.
  std::string sensorName(const YAML::Node& n, const std::string& key, bool marker) {
    const std::string name = text(n, key);
    if (name.find_first_of(",\n\r\"") != std::string::npos || name.front() == '#' ||
        std::isspace(static_cast<unsigned char>(name.front())) ||
        std::isspace(static_cast<unsigned char>(name.back())))
      fail(n, key,
           "name '" + name +
               "' cannot be a CSV column (no commas, quotes, leading '#' or surrounding spaces)");
    if (!marker && isTimeName(name))
      fail(n, key, "name '" + name + "' is reserved for the log's time column");
    std::vector<std::string> cols;
    if (marker)
      cols = {name + ".x", name + ".y", name + ".z"};
    else
      cols = {name};
    if (!names_.insert(name).second) fail(n, key, "name '" + name + "' is used twice");
    for (const std::string& c : cols)
      if (!columns_.insert(c).second)
        fail(n, key, "name '" + name + "' gives log column '" + c + "', which another sensor has");
    return name;
  }

  static constexpr const char* kTop = "(top level)";

 private:
  std::string file_;
  const RobotModel& robot_;
  std::set<std::string> names_, columns_;
};

void readFrame(Reader& rd, const YAML::Node& node, SensorSet* s, SensorParameters* th) {
  if (node.IsNull()) return;
  auto f = rd.fields(node, "mocap.frame", {"translation", "rpy", "quaternion", "fixed", "std"});
  if (f.count("translation"))
    th->mocap.translation = rd.vector(f["translation"], "mocap.frame.translation", 3);
  if (f.count("fixed")) s->mocap_frame_fixed = rd.boolean(f["fixed"], "mocap.frame.fixed");
  std::optional<Eigen::Quaterniond> from_q, from_rpy;
  if (f.count("quaternion")) {
    const Eigen::Vector4d q = rd.vector(f["quaternion"], "mocap.frame.quaternion", 4);
    if (!(q.norm() > 1e-9))
      rd.fail(f["quaternion"], "mocap.frame.quaternion", "a zero quaternion is no rotation");
    from_q = unitQuaternion(Eigen::Quaterniond(q[0], q[1], q[2], q[3]));
  }
  if (f.count("rpy")) from_rpy = fromRpy(rd.vector(f["rpy"], "mocap.frame.rpy", 3));
  if (from_q && from_rpy) {
    const double gap = from_q->angularDistance(*from_rpy);  // q and -q are the same rotation
    if (gap > 1e-6) {
      std::ostringstream msg;
      msg << "rpy and quaternion (line " << f["quaternion"].Mark().line + 1
          << ") are different rotations (" << gap << " rad apart); give one of them";
      rd.fail(f["rpy"], "mocap.frame.rpy", msg.str());
    }
  }
  // The quaternion is the more precise of the two when both are given.
  if (from_q)
    th->mocap.rotation = *from_q;
  else if (from_rpy)
    th->mocap.rotation = *from_rpy;
}

void readMocap(Reader& rd, const YAML::Node& node, SensorSet* s, SensorParameters* th) {
  if (node.IsNull()) return;
  auto f = rd.fields(node, "mocap", {"sigma", "frame", "markers"});
  // mocap.sigma first: it is the σ of every marker that has no own.
  if (f.count("sigma")) s->mocap_sigma = rd.sigma(f["sigma"], "mocap.sigma");
  if (f.count("frame")) readFrame(rd, f["frame"], s, th);
  if (!f.count("markers") || f["markers"].IsNull()) return;
  const YAML::Node& list = f["markers"];
  if (!list.IsSequence()) rd.fail(list, "mocap.markers", "expected a list of markers");
  for (size_t i = 0; i < list.size(); ++i) {
    const std::string key = "mocap.markers[" + std::to_string(i) + "]";
    auto m = rd.fields(list[i], key,
                       {"name", "link", "position", "fixed", "sigma", "std", "residual"});
    if (!m.count("name")) rd.fail(list[i], key + ".name", "missing (every marker needs a name)");
    if (!m.count("link")) rd.fail(list[i], key + ".link", "missing (every marker needs a link)");
    MarkerConfig mc;
    mc.name = rd.sensorName(m["name"], key + ".name", true);
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
    if (!f.count("name")) rd.fail(list[i], key + ".name", "missing (every sensor needs a name)");
    if (!f.count("joint"))
      rd.fail(list[i], key + ".joint", "missing (a joint sensor needs its joint)");
    JointSensorConfig c;
    c.name = rd.sensorName(f["name"], key + ".name", false);
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
    if (!f.count("name")) rd.fail(list[i], key + ".name", "missing (every sensor needs a name)");
    TendonSensorConfig c;
    c.name = rd.sensorName(f["name"], key + ".name", false);
    GainBias gb;
    readGainBias(rd, f, key, &c.sigma, &c.fixed, &gb);
    const bool has_path = f.count("path") > 0, has_coupling = f.count("coupling") > 0;
    if (has_path && has_coupling)
      rd.fail(f["coupling"], key + ".coupling", "give either path or coupling, not both");
    if (!has_path && !has_coupling)
      rd.fail(list[i], key, "needs a path (anchor points) or a coupling (joint: coefficient)");
    if (has_path) {
      const YAML::Node& p = f["path"];
      if (!p.IsSequence()) rd.fail(p, key + ".path", "expected a list of {link, point}");
      if (p.size() < 2)
        rd.fail(p, key + ".path",
                "a path needs at least two points, got " + std::to_string(p.size()));
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
      std::map<std::string, int> seen;  // joint -> line
      for (auto it = cp.begin(); it != cp.end(); ++it) {
        const std::string jn = it->first.IsScalar() ? it->first.Scalar() : "";
        const std::string ck = key + ".coupling." + jn;
        if (seen.count(jn))
          rd.fail(it->first, ck,
                  "given twice (first on line " + std::to_string(seen[jn]) + ")");
        seen[jn] = it->first.Mark().line + 1;
        CouplingTerm term;
        term.joint = rd.joint(it->first, ck);
        term.joint_name = jn;
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
  static const char* kHex = "0123456789ABCDEF";
  std::string out = "\"";
  for (const char ch : s) {
    const unsigned char c = static_cast<unsigned char>(ch);
    switch (c) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\n': out += "\\n"; break;
      case '\r': out += "\\r"; break;
      case '\t': out += "\\t"; break;
      default:
        if (c < 0x20 || c == 0x7f) {
          out += "\\x";
          out += kHex[c >> 4];
          out += kHex[c & 15];
        } else {
          out += ch;
        }
    }
  }
  return out + "\"";
}

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

const char* boolean(bool b) { return b ? "true" : "false"; }

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

// ---- inference ----

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

}  // namespace

SensorsFile parseSensorsYaml(const std::string& text, const std::string& source_name,
                             const RobotModel& model) {
  Reader rd(source_name, model);
  std::vector<YAML::Node> docs;
  try {
    docs = YAML::LoadAll(text);
  } catch (const YAML::ParserException& e) {
    throw InputError(source_name, e.mark.line + 1, e.mark.column + 1, "malformed YAML: " + e.msg);
  }
  if (docs.size() > 1)
    rd.fail(docs[1], Reader::kTop, "the file holds more than one YAML document");
  SensorsFile out;
  const YAML::Node root = docs.empty() ? YAML::Node() : docs[0];
  if (!root.IsNull()) {
    auto f = rd.fields(root, Reader::kTop, {"mocap", "joint_sensors", "tendon_sensors", "summary"});
    if (f.count("mocap")) readMocap(rd, f["mocap"], &out.sensors, &out.theta);
    if (f.count("joint_sensors"))
      readJointSensors(rd, f["joint_sensors"], &out.sensors, &out.theta);
    if (f.count("tendon_sensors"))
      readTendonSensors(rd, f["tendon_sensors"], &out.sensors, &out.theta);
  }
  if (out.sensors.markers.empty() && out.sensors.joint_sensors.empty() &&
      out.sensors.tendon_sensors.empty())
    throw InputError(source_name,
                     "no sensors: the file gives no mocap.markers, joint_sensors or tendon_sensors");
  return out;
}

SensorsFile loadSensorsFile(const std::string& path, const RobotModel& model) {
  return parseSensorsYaml(readTextFile(path), path, model);
}

std::string sensorsToYaml(const SensorSet& s, const SensorParameters& th,
                          const CalibrationResult* result) {
  // σ are the calibration's (adapted) values when there is one.
  const SensorSet& sig = result ? result->sensors : s;
  assert(sig.markers.size() == s.markers.size());
  assert(sig.joint_sensors.size() == s.joint_sensors.size());
  assert(sig.tendon_sensors.size() == s.tendon_sensors.size());
  assert(th.marker_position.size() == s.markers.size());
  assert(th.joint_sensor.size() == s.joint_sensors.size());
  assert(th.tendon_sensor.size() == s.tendon_sensors.size());
  std::string o;
  if (result) o += "# Calibration written by stac_calib; feed it back with --sensors.\n";
  if (!s.markers.empty()) {
    const Eigen::Quaterniond q = unitQuaternion(th.mocap.rotation);
    o += "mocap:\n";
    o += "  sigma: " + num(sig.mocap_sigma) + "\n";
    o += "  frame:\n";
    o += "    translation: " + vec(th.mocap.translation) + "\n";
    o += "    rpy: " + vec(toRpy(q)) + "\n";
    o += "    quaternion: " + vec(Eigen::Vector4d(q.w(), q.x(), q.y(), q.z())) + "\n";
    o += "    fixed: " + std::string(boolean(s.mocap_frame_fixed)) + "\n";
    if (result)
      o += "    std: {translation: " + vec(result->std.mocap_translation) +
           ", rotation: " + vec(result->std.mocap_rotation) + "}\n";
    o += "  markers:\n";
    for (size_t m = 0; m < s.markers.size(); ++m) {
      const MarkerConfig& mc = s.markers[m];
      o += "    - name: " + scalar(mc.name) + "\n";
      o += "      link: " + scalar(mc.link_name) + "\n";
      o += "      position: " + vec(th.marker_position[m]) + "\n";
      o += "      fixed: " + std::string(boolean(mc.fixed)) + "\n";
      const MarkerConfig& ms = sig.markers[m];
      if (ms.sigma_overridden || ms.sigma != sig.mocap_sigma)
        o += "      sigma: " + num(ms.sigma) + "\n";
      if (result) {
        if (m < result->std.marker_position.size())
          o += "      std: {position: " + vec(result->std.marker_position[m]) + "}\n";
        if (m < result->marker_residual.size())
          o += residualLine("      ", result->marker_residual[m]);
      }
    }
  }
  auto gainBias = [&](const GainBias& gb, double sigma, bool fixed) {
    o += "    gain: " + num(gb.gain) + "\n";
    o += "    bias: " + num(gb.bias) + "\n";
    o += "    sigma: " + num(sigma) + "\n";
    o += "    fixed: " + std::string(boolean(fixed)) + "\n";
  };
  auto extras = [&](const std::vector<GainBias>& std_of, const std::vector<ResidualStats>& res,
                    size_t i) {
    if (!result) return;
    if (i < std_of.size())
      o += "    std: {gain: " + num(std_of[i].gain) + ", bias: " + num(std_of[i].bias) + "}\n";
    if (i < res.size()) o += residualLine("    ", res[i]);
  };
  if (!s.joint_sensors.empty()) {
    o += "joint_sensors:\n";
    for (size_t j = 0; j < s.joint_sensors.size(); ++j) {
      const JointSensorConfig& c = s.joint_sensors[j];
      o += "  - name: " + scalar(c.name) + "\n";
      o += "    joint: " + scalar(c.joint_name) + "\n";
      gainBias(th.joint_sensor[j], sig.joint_sensors[j].sigma, c.fixed);
      if (result) extras(result->std.joint_sensor, result->joint_residual, j);
    }
  }
  if (!s.tendon_sensors.empty()) {
    o += "tendon_sensors:\n";
    for (size_t j = 0; j < s.tendon_sensors.size(); ++j) {
      const TendonSensorConfig& c = s.tendon_sensors[j];
      o += "  - name: " + scalar(c.name) + "\n";
      gainBias(th.tendon_sensor[j], sig.tendon_sensors[j].sigma, c.fixed);
      if (c.kind == TendonSensorConfig::Kind::kPath) {
        o += "    path:\n";
        for (const PathAnchor& a : c.path)
          o += "      - {link: " + scalar(a.link_name) + ", point: " + vec(a.point) + "}\n";
      } else {
        o += "    coupling: {";
        for (size_t k = 0; k < c.coupling.size(); ++k)
          o += (k ? ", " : "") + scalar(c.coupling[k].joint_name) + ": " +
               num(c.coupling[k].coefficient);
        o += "}\n";
      }
      if (result) extras(result->std.tendon_sensor, result->tendon_residual, j);
    }
  }
  if (result) {
    const CalibrationSummary& sm = result->summary;
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
    if (sm.unidentifiable.empty()) {
      o += "  unidentifiable: []\n";
    } else {
      o += "  unidentifiable:\n";
      for (const UnidentifiableDirection& d : sm.unidentifiable) {
        o += "    - parameters: [";
        for (size_t k = 0; k < d.parameters.size(); ++k)
          o += (k ? ", " : "") + quoted(d.parameters[k]);
        o += "]\n      reason: " + quoted(d.reason) + "\n";
      }
    }
    if (sm.downweighted.empty()) {
      o += "  downweighted: []\n";
    } else {
      o += "  downweighted:\n";
      for (const DownweightedReading& d : sm.downweighted)
        o += "    - {frame: " + std::to_string(d.frame) + ", sensor: " + quoted(d.sensor) +
             ", weight: " + num(d.weight) + "}\n";
    }
  }
  return o;
}

SensorsFile inferSensorsFromLog(const Log& log, const RobotModel& model) {
  SensorsFile out;
  out.sensors.mocap_sigma = 0.002;
  const std::set<std::string> columns(log.columns.begin(), log.columns.end());
  std::set<std::string> placed;
  for (const std::string& c : log.columns) {
    if (placed.count(c)) continue;
    if (const auto j = model.movableJointIndex(c)) {
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
    const std::string base = markerBase(c);
    if (base.empty()) continue;
    const auto link = model.linkIndex(base);
    if (!link) continue;
    const std::string x = base + ".x", y = base + ".y", z = base + ".z";
    if (!columns.count(x) || !columns.count(y) || !columns.count(z)) continue;
    if (placed.count(x) || placed.count(y) || placed.count(z)) continue;  // a joint took one
    MarkerConfig m;
    m.name = base;
    m.link_name = base;
    m.link = *link;
    m.sigma = out.sensors.mocap_sigma;
    out.sensors.markers.push_back(m);
    out.theta.marker_position.push_back(Eigen::Vector3d::Zero());
    placed.insert({x, y, z});
  }

  // Every other column is an error; each gets the closest name as a hint.
  std::vector<std::pair<std::string, std::string>> candidates;  // (name, kind)
  for (const MovableJoint& j : model.movableJoints()) candidates.emplace_back(j.name, "joint");
  for (const Link& l : model.links()) candidates.emplace_back(l.name, "link");
  const auto& all_joints = model.allJointNames();
  std::string unplaced;
  int count = 0;
  for (const std::string& c : log.columns) {
    if (placed.count(c)) continue;
    ++count;
    const std::string base = markerBase(c);
    const std::string key = base.empty() ? c : base;
    std::string hint;
    if (!base.empty() && model.linkIndex(base)) {
      hint = "a marker on link '" + base + "' needs all of " + base + ".x, " + base + ".y and " +
             base + ".z";
    } else if (std::find(all_joints.begin(), all_joints.end(), c) != all_joints.end()) {
      hint = "joint '" + c + "' is fixed: it has no angle to sense";
    } else {
      const std::pair<std::string, std::string>* best = nullptr;
      size_t best_d = std::string::npos;
      for (const auto& cand : candidates) {
        // A column with an .x/.y/.z suffix is meant as a marker: on a link.
        if (!base.empty() && cand.second != "link") continue;
        const size_t d = editDistance(key, cand.first);
        if (d < best_d) best_d = d, best = &cand;
      }
      if (best)
        hint = "closest joint or link: " + best->second + " '" + best->first +
               "'; did you mean '" + (base.empty() || best->second != "link"
                                          ? best->first
                                          : best->first + c.substr(base.size())) +
               "'?";
      else
        hint = "the robot has no joint or link to match";
    }
    unplaced += "\n  " + c + " (" + hint + ")";
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
