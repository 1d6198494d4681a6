// The sensors file's reader (SPEC §3): strict, on yaml-cpp, and every error
// names the file, the line and the key.
#include "stac/sensors_file.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <set>
#include <sstream>

#include "io/log_header.hpp"
#include "io/rpy.hpp"
#include "io/yaml_guard.hpp"
#include "io/yaml_number.hpp"
#include "stac/error.hpp"
#include "stac/file_io.hpp"

namespace stac {
namespace {


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
    const std::optional<double> v = parseYamlNumber(s);
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

  // `fixed`: true or false (every part), or the list of the parts to hold
  // among `parts` (the item's own, e.g. gain and bias). Returns, per part,
  // whether it is held.
  std::vector<bool> heldParts(const YAML::Node& n, const std::string& key, const char* item,
                              const std::vector<std::string>& parts) const {
    if (!n.IsSequence()) return std::vector<bool>(parts.size(), boolean(n, key));
    std::string list;
    for (const std::string& p : parts) list += (list.empty() ? "" : ", ") + p;
    std::vector<bool> held(parts.size(), false);
    std::map<std::string, int> seen;  // part -> line
    for (const YAML::Node& e : n) {
      if (!e.IsScalar() || e.Tag() == "!")
        fail(e, key, "expected true, false or a list of parameter names (" + list + ")");
      const std::string& name = e.Scalar();
      const auto it = std::find(parts.begin(), parts.end(), name);
      if (it == parts.end())
        fail(e, key,
             kAnyPart.count(name) ? std::string(item) + " has no " + name + " (its parameters: " +
                                        list + ")"
                                  : "unknown parameter '" + name + "' (expected some of: " +
                                        list + ")");
      if (seen.count(name))
        fail(e, key,
             "'" + name + "' given twice (first on line " + std::to_string(seen[name]) + ")");
      seen[name] = e.Mark().line + 1;
      held[it - parts.begin()] = true;
    }
    return held;
  }

  // A marker's position is held or free as a whole: no list.
  bool markerFixed(const YAML::Node& n, const std::string& key) const {
    if (!n.IsSequence()) return boolean(n, key);
    const YAML::Node at = n.size() > 0 ? n[0] : n;
    const std::string name = at.IsScalar() ? at.Scalar() : "";
    fail(at, key,
         (kAnyPart.count(name) && name != "position" ? "a marker has no " + name + "; " : "") +
             std::string("a marker's position is held or free as a whole (expected true or "
                         "false, not a list)"));
  }

  FixedGainBias fixedGainBias(const YAML::Node& n, const std::string& key,
                              const char* item) const {
    const std::vector<bool> held = heldParts(n, key, item, {"gain", "bias"});
    return {held[0], held[1]};
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

  // A sensor's or marker's name. It is the default of its log column(s)
  // (claimed apart, by claimColumn), so it must be one that a CSV can hold.
  std::string sensorName(const YAML::Node& n, const std::string& key) {
    const std::string name = text(n, key);
    if (!names_.insert(name).second) fail(n, key, "name '" + name + "' is used twice");
    return name;
  }

  // A log column named by `column:`, `columns:` or `ignore_columns:`.
  std::string columnName(const YAML::Node& n, const std::string& key) const {
    const std::string name = text(n, key);
    requireCsvName(n, key, "column", name);
    return name;
  }

  // Notes that the item at `key` reads log column `column` (given by
  // `column:`/`columns:` when mapped, else its name): no two may share one,
  // and none may be the time column.
  void claimColumn(const YAML::Node& at, const std::string& key, const std::string& column,
                   bool mapped) {
    if (!mapped) requireCsvName(at, key, "name", column);
    if (io::isTimeName(column))
      fail(at, key,
           mapped ? "column '" + column + "' is the log's time column, not a sensor's"
                  : "name '" + column + "' is reserved for the log's time column");
    const auto [it, fresh] = columns_.emplace(column, ColumnKey{key, line(at), mapped});
    if (fresh) return;
    const std::string first =
        " (" + it->second.key + ", line " + std::to_string(it->second.line) + ")";
    fail(at, key,
         mapped ? "column '" + column + "' is read by another sensor too" + first
                : "name '" + keyName(at) + "' gives log column '" + column +
                      "', which another sensor has" + first);
  }

  // An `ignore_columns` entry: no sensor may read it.
  void ignoreColumn(const YAML::Node& at, const std::string& key, const std::string& column) {
    const auto [it, fresh] = columns_.emplace(column, ColumnKey{key, line(at), false});
    if (fresh) return;
    fail(at, key,
         "column '" + column + "' is " +
             (it->second.key.rfind("ignore_columns", 0) == 0
                  ? "listed twice (" + it->second.key + ", line " +
                        std::to_string(it->second.line) + ")"
                  : "read by " + it->second.key + " (line " + std::to_string(it->second.line) +
                        "): a column is a sensor's or ignored, not both"));
  }

  ColumnKeys columnKeys() const { return columns_; }

  static constexpr const char* kTop = "(top level)";
  // Every parameter name some item's `fixed` list may give.
  inline static const std::set<std::string> kAnyPart = {"gain", "bias", "rotation",
                                                        "translation", "position", "xyz", "rpy"};

 private:
  std::string file_;
  const RobotModel& robot_;
  static int line(const YAML::Node& n) { return n.Mark().line >= 0 ? n.Mark().line + 1 : 0; }
  static std::string keyName(const YAML::Node& n) { return n.IsScalar() ? n.Scalar() : ""; }

  void requireCsvName(const YAML::Node& n, const std::string& key, const char* what,
                      const std::string& name) const {
    if (name.find_first_of(",\n\r\"") != std::string::npos || name.front() == '#' ||
        std::isspace(static_cast<unsigned char>(name.front())) ||
        std::isspace(static_cast<unsigned char>(name.back())))
      fail(n, key,
           std::string(what) + " '" + name +
               "' cannot be a CSV column (no commas, quotes, leading '#' or surrounding spaces)");
  }

  std::set<std::string> names_;
  ColumnKeys columns_;  // log column -> the key that reads or ignores it
};

void readFrame(Reader& rd, const YAML::Node& node, SensorSet* s, SensorParameters* th) {
  if (node.IsNull()) return;
  auto f = rd.fields(node, "mocap.frame", {"translation", "rpy", "quaternion", "fixed", "std"});
  if (f.count("translation"))
    th->mocap.translation = rd.vector(f["translation"], "mocap.frame.translation", 3);
  if (f.count("fixed")) {
    const std::vector<bool> held = rd.heldParts(f["fixed"], "mocap.frame.fixed",
                                                "the mocap frame", {"rotation", "translation"});
    s->mocap_frame_fixed = {held[0], held[1]};
  }
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

// A marker's `columns: [x, y, z]`, or its default <name>.x/.y/.z.
void readMarkerColumns(Reader& rd, std::map<std::string, YAML::Node>& m, const std::string& key,
                       MarkerConfig* mc) {
  if (!m.count("columns")) {
    for (const std::string& c : mc->logColumns())
      rd.claimColumn(m["name"], key + ".name", c, false);
    return;
  }
  const YAML::Node& list = m["columns"];
  const std::string ck = key + ".columns";
  if (!list.IsSequence() || list.size() != 3)
    rd.fail(list, ck, "expected the list of the x, y and z columns ([<x>, <y>, <z>])");
  for (int i = 0; i < 3; ++i) {
    const std::string ik = ck + "[" + std::to_string(i) + "]";
    mc->columns[i] = rd.columnName(list[i], ik);
    rd.claimColumn(list[i], ik, mc->columns[i], true);
  }
}

// A joint or tendon sensor's `column:`, or its default: its name.
template <class SensorConfig>
void readColumn(Reader& rd, std::map<std::string, YAML::Node>& f, const std::string& key,
                SensorConfig* c) {
  if (!f.count("column")) {
    rd.claimColumn(f["name"], key + ".name", c->name, false);
    return;
  }
  c->column = rd.columnName(f["column"], key + ".column");
  rd.claimColumn(f["column"], key + ".column", c->column, true);
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
                       {"name", "link", "position", "fixed", "sigma", "columns", "std",
                        "residual"});
    if (!m.count("name")) rd.fail(list[i], key + ".name", "missing (every marker needs a name)");
    if (!m.count("link")) rd.fail(list[i], key + ".link", "missing (every marker needs a link)");
    MarkerConfig mc;
    mc.name = rd.sensorName(m["name"], key + ".name");
    readMarkerColumns(rd, m, key, &mc);
    mc.link = rd.link(m["link"], key + ".link");
    mc.link_name = m["link"].Scalar();
    Eigen::Vector3d d = Eigen::Vector3d::Zero();
    if (m.count("position")) d = rd.vector(m["position"], key + ".position", 3);
    if (m.count("fixed")) mc.fixed = rd.markerFixed(m["fixed"], key + ".fixed");
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
                  const char* item, double* sigma, FixedGainBias* fixed, GainBias* gb) {
  if (f.count("gain")) gb->gain = rd.number(f["gain"], key + ".gain");
  if (f.count("bias")) gb->bias = rd.number(f["bias"], key + ".bias");
  if (f.count("sigma")) *sigma = rd.sigma(f["sigma"], key + ".sigma");
  if (f.count("fixed")) *fixed = rd.fixedGainBias(f["fixed"], key + ".fixed", item);
}

void readJointSensors(Reader& rd, const YAML::Node& list, SensorSet* s, SensorParameters* th) {
  if (list.IsNull()) return;
  if (!list.IsSequence()) rd.fail(list, "joint_sensors", "expected a list of sensors");
  for (size_t i = 0; i < list.size(); ++i) {
    const std::string key = "joint_sensors[" + std::to_string(i) + "]";
    auto f = rd.fields(list[i], key,
                       {"name", "joint", "column", "gain", "bias", "sigma", "fixed", "std",
                        "residual"});
    if (!f.count("name")) rd.fail(list[i], key + ".name", "missing (every sensor needs a name)");
    if (!f.count("joint"))
      rd.fail(list[i], key + ".joint", "missing (a joint sensor needs its joint)");
    JointSensorConfig c;
    c.name = rd.sensorName(f["name"], key + ".name");
    readColumn(rd, f, key, &c);
    c.joint = rd.joint(f["joint"], key + ".joint");
    c.joint_name = f["joint"].Scalar();
    GainBias gb;
    readGainBias(rd, f, key, "a joint sensor", &c.sigma, &c.fixed, &gb);
    s->joint_sensors.push_back(c);
    th->joint_sensor.push_back(gb);
  }
}

// A path tendon's anchors, in order from one end to the other.
void readPath(Reader& rd, const YAML::Node& p, const std::string& key, TendonSensorConfig* c) {
  if (!p.IsSequence()) rd.fail(p, key + ".path", "expected a list of {link, point}");
  if (p.size() < 2)
    rd.fail(p, key + ".path", "a path needs at least two points, got " + std::to_string(p.size()));
  for (size_t k = 0; k < p.size(); ++k) {
    const std::string pk = key + ".path[" + std::to_string(k) + "]";
    auto a = rd.fields(p[k], pk, {"link", "point"});
    if (!a.count("link")) rd.fail(p[k], pk + ".link", "missing");
    if (!a.count("point")) rd.fail(p[k], pk + ".point", "missing");
    PathAnchor anchor;
    anchor.link = rd.link(a["link"], pk + ".link");
    anchor.link_name = a["link"].Scalar();
    anchor.point = rd.vector(a["point"], pk + ".point", 3);
    c->path.push_back(anchor);
  }
}

// A coupling tendon's joint: coefficient terms. Reader::fields does not
// serve here: the keys are joint names, not a fixed set.
void readCoupling(Reader& rd, const YAML::Node& cp, const std::string& key,
                  TendonSensorConfig* c) {
  if (!cp.IsMap() || cp.size() == 0)
    rd.fail(cp, key + ".coupling", "expected a mapping of joint: coefficient");
  std::map<std::string, int> seen;  // joint -> line
  for (auto it = cp.begin(); it != cp.end(); ++it) {
    const std::string jn = it->first.IsScalar() ? it->first.Scalar() : "";
    const std::string ck = key + ".coupling." + jn;
    if (seen.count(jn))
      rd.fail(it->first, ck, "given twice (first on line " + std::to_string(seen[jn]) + ")");
    seen[jn] = it->first.Mark().line + 1;
    CouplingTerm term;
    term.joint = rd.joint(it->first, ck);
    term.joint_name = jn;
    term.coefficient = rd.number(it->second, ck);
    c->coupling.push_back(term);
  }
}

void readTendonSensors(Reader& rd, const YAML::Node& list, SensorSet* s, SensorParameters* th) {
  if (list.IsNull()) return;
  if (!list.IsSequence()) rd.fail(list, "tendon_sensors", "expected a list of sensors");
  for (size_t i = 0; i < list.size(); ++i) {
    const std::string key = "tendon_sensors[" + std::to_string(i) + "]";
    auto f = rd.fields(list[i], key, {"name", "column", "gain", "bias", "sigma", "fixed",
                                      "path", "coupling", "std", "residual"});
    if (!f.count("name")) rd.fail(list[i], key + ".name", "missing (every sensor needs a name)");
    TendonSensorConfig c;
    c.name = rd.sensorName(f["name"], key + ".name");
    readColumn(rd, f, key, &c);
    GainBias gb;
    readGainBias(rd, f, key, "a tendon sensor", &c.sigma, &c.fixed, &gb);
    const bool has_path = f.count("path") > 0, has_coupling = f.count("coupling") > 0;
    if (has_path && has_coupling)
      rd.fail(f["coupling"], key + ".coupling", "give either path or coupling, not both");
    if (!has_path && !has_coupling)
      rd.fail(list[i], key, "needs a path (anchor points) or a coupling (joint: coefficient)");
    if (has_path) {
      readPath(rd, f["path"], key, &c);
    } else {
      c.kind = TendonSensorConfig::Kind::kCoupling;
      readCoupling(rd, f["coupling"], key, &c);
    }
    s->tendon_sensors.push_back(c);
    th->tendon_sensor.push_back(gb);
  }
}

// The link a URDF joint attaches (any joint but the root's: a fixed joint's
// origin is geometry too).
int originLink(Reader& rd, const RobotModel& robot, const YAML::Node& n, const std::string& key) {
  const std::string name = rd.text(n, key);
  if (const std::optional<int> link = robot.linkOfJoint(name)) return *link;
  rd.fail(n, key, "unknown joint '" + name + "' (not in " + robot.sourceName() + ")");
}

double priorStd(Reader& rd, std::map<std::string, YAML::Node>& f, const char* part) {
  if (!f.count(part)) return 0.0;
  const std::string key = std::string("joint_origins.prior_std.") + part;
  const double v = rd.number(f[part], key);
  if (!(v > 0)) rd.fail(f[part], key, "a prior std must be positive, got " + f[part].Scalar());
  return v;
}

// SPEC §3 "Kinematic calibration: joint origins".
void readJointOrigins(Reader& rd, const RobotModel& robot, const YAML::Node& node, SensorSet* s,
                      SensorParameters* th) {
  auto f = rd.fields(node, "joint_origins", {"prior_std", "joints"});
  if (f.count("prior_std")) {
    auto p = rd.fields(f["prior_std"], "joint_origins.prior_std", {"xyz", "rpy"});
    s->origin_prior = {priorStd(rd, p, "xyz"), priorStd(rd, p, "rpy")};
  }
  if (!f.count("joints")) return;
  const YAML::Node& list = f["joints"];
  if (!list.IsSequence()) rd.fail(list, "joint_origins.joints", "expected a list of joints");
  std::map<int, int> seen;  // link -> line
  for (size_t i = 0; i < list.size(); ++i) {
    const std::string key = "joint_origins.joints[" + std::to_string(i) + "]";
    auto j = rd.fields(list[i], key, {"joint", "xyz", "rpy", "fixed", "std"});
    if (!j.count("joint")) rd.fail(list[i], key + ".joint", "missing (which joint's origin)");
    JointOriginConfig c;
    c.link = originLink(rd, robot, j["joint"], key + ".joint");
    c.joint_name = j["joint"].Scalar();
    if (seen.count(c.link))
      rd.fail(j["joint"], key + ".joint",
              "joint '" + c.joint_name + "' given twice (first on line " +
                  std::to_string(seen[c.link]) + ")");
    seen[c.link] = j["joint"].Mark().line + 1;
    OriginCorrection o;
    if (j.count("xyz")) o.xyz = rd.vector(j["xyz"], key + ".xyz", 3);
    if (j.count("rpy")) o.rpy = rd.vector(j["rpy"], key + ".rpy", 3);
    if (j.count("fixed")) {
      const std::vector<bool> held =
          rd.heldParts(j["fixed"], key + ".fixed", "a joint origin", {"xyz", "rpy"});
      c.fixed = {held[0], held[1]};
    }
    s->joint_origins.push_back(c);
    th->joint_origin.push_back(o);
  }
}

void readIgnoreColumns(Reader& rd, const YAML::Node& list, SensorSet* s) {
  if (!list.IsSequence()) rd.fail(list, "ignore_columns", "expected a list of log columns");
  for (size_t i = 0; i < list.size(); ++i) {
    const std::string key = "ignore_columns[" + std::to_string(i) + "]";
    const std::string column = rd.columnName(list[i], key);
    rd.ignoreColumn(list[i], key, column);
    s->ignore_columns.push_back(column);
  }
}

}  // namespace

SensorsFile parseSensorsYaml(const std::string& text, const std::string& source_name,
                             const RobotModel& model) {
  Reader rd(source_name, model);
  std::vector<YAML::Node> docs;
  checkYamlFlowIndicators(text, source_name);  // what would hang yaml-cpp never reaches it
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
    auto f = rd.fields(root, Reader::kTop,
                       {"mocap", "joint_sensors", "tendon_sensors", "joint_origins",
                        "ignore_columns", "summary"});
    if (f.count("mocap")) readMocap(rd, f["mocap"], &out.sensors, &out.theta);
    if (f.count("joint_sensors"))
      readJointSensors(rd, f["joint_sensors"], &out.sensors, &out.theta);
    if (f.count("tendon_sensors"))
      readTendonSensors(rd, f["tendon_sensors"], &out.sensors, &out.theta);
    if (f.count("joint_origins"))
      readJointOrigins(rd, model, f["joint_origins"], &out.sensors, &out.theta);
    // After the sensors: an ignored column must be none of theirs.
    if (f.count("ignore_columns")) readIgnoreColumns(rd, f["ignore_columns"], &out.sensors);
  }
  out.column_keys = rd.columnKeys();
  if (out.sensors.markers.empty() && out.sensors.joint_sensors.empty() &&
      out.sensors.tendon_sensors.empty())
    throw InputError(source_name,
                     "no sensors: the file gives no mocap.markers, joint_sensors or tendon_sensors");
  return out;
}

SensorsFile loadSensorsFile(const std::string& path, const RobotModel& model) {
  return parseSensorsYaml(readTextFile(path), path, model);
}

}  // namespace stac
