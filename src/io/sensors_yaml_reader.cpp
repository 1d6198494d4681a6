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
#include "io/sensors_yaml_fields.hpp"
#include "io/yaml_guard.hpp"
#include "io/yaml_number.hpp"
#include "stac/error.hpp"
#include "stac/file_io.hpp"

namespace stac {
namespace {

using sensors_yaml::Reader;

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
