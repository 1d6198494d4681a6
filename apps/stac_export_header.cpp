// stac_export_header: a calibration as a self-contained C99 header for
// firmware.
//
//   stac_export_header --sensors calibration.yaml --urdf robot.urdf
//                      --output calibration.h
//
// The header holds, per sensor, macros named STAC_<SENSOR>_... (the sensor's
// name made a C identifier: every character outside [A-Za-z0-9_] becomes '_',
// upper-cased) with its gain and bias, and static inline conversions of a raw
// reading: stac_<sensor>_to_radians (a joint sensor on a revolute or
// continuous joint), stac_<sensor>_to_metres (on a prismatic joint),
// stac_<sensor>_to_length (a tendon sensor), each (raw - bias) / gain. Markers
// give their link and position in the link frame, and the mocap frame its
// quaternion (w, x, y, z) and translation. Numbers are written in the
// shortest form that reads back to the same double. Two sensors whose
// identifiers would clash are an error (exit 2), never a silent rename.
#include <cctype>
#include <charconv>
#include <filesystem>
#include <cmath>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "common/cli.hpp"
#include "common/outputs.hpp"
#include "stac/error.hpp"
#include "stac/robot_model.hpp"
#include "stac/sensors_file.hpp"

#ifndef STAC_VERSION
#define STAC_VERSION "0.0.0"
#endif

namespace {

using stac::cli::Args;
using stac::cli::Option;
using stac::cli::UsageError;
namespace fs = std::filesystem;

const char* kSynopsis =
    "usage: stac_export_header --sensors calibration.yaml --urdf robot.urdf\n"
    "                          --output calibration.h\n"
    "\n"
    "Writes a calibration (SPEC §3 sensors file) as a self-contained C99 header\n"
    "for firmware: per sensor STAC_<NAME>_GAIN/_BIAS and a static inline\n"
    "stac_<name>_to_radians(raw) = (raw - bias) / gain (to_metres on a prismatic\n"
    "joint, to_length for a tendon sensor); marker positions; the mocap frame.";

const std::vector<Option> kOptions = {
    {"sensors", "FILE", "the calibration (or any sensors file, YAML)", true},
    {"urdf", "FILE", "robot model (URDF) the sensors file refers to", true},
    {"output", "FILE", "the C header to write", true},
};

// The shortest decimal that reads back as exactly v, always a double literal
// (negative values parenthesised, so that macros expand safely).
std::string number(double v) {
  char buf[64];
  const auto res = std::to_chars(buf, buf + sizeof buf, v);
  std::string s(buf, res.ptr);
  if (s.find_first_of(".eEn") == std::string::npos) s += ".0";
  return std::signbit(v) ? "(" + s + ")" : s;
}

// A C string literal: quotes, backslashes and '?' (trigraphs) escaped,
// other non-printable bytes in octal.
std::string cString(const std::string& s) {
  std::string out = "\"";
  for (unsigned char ch : s) {
    if (ch == '"' || ch == '\\' || ch == '?') {
      out += '\\';
      out += static_cast<char>(ch);
    } else if (ch < 0x20 || ch >= 0x7f) {
      const char digits[] = {'\\', static_cast<char>('0' + (ch >> 6)),
                             static_cast<char>('0' + ((ch >> 3) & 7)),
                             static_cast<char>('0' + (ch & 7)), '\0'};
      out += digits;
    } else {
      out += static_cast<char>(ch);
    }
  }
  return out + "\"";
}

// Text safe inside a /* */ comment.
std::string commentText(std::string s) {
  for (char& ch : s)
    if (ch == '\n' || ch == '\r' || static_cast<unsigned char>(ch) < 0x20) ch = ' ';
  for (std::size_t i; (i = s.find("*/")) != std::string::npos;) s.replace(i, 2, "* /");
  return s;
}

std::string identifier(const std::string& name, bool upper) {
  std::string id;
  for (unsigned char ch : name) {
    const bool ok = std::isalnum(ch) || ch == '_';
    id += ok ? static_cast<char>(upper ? std::toupper(ch) : std::tolower(ch)) : '_';
  }
  return id;
}

// Emits C text and refuses to define one identifier twice (two sensor names
// that sanitise to the same identifier).
class HeaderWriter {
 public:
  void line(const std::string& text = "") { out_ << text << "\n"; }
  void define(const std::string& macro, const std::string& value,
              const std::string& owner) {
    claim(macro, owner);
    out_ << "#define " << macro << " " << value << "\n";
  }
  void claim(const std::string& id, const std::string& owner) {
    auto [it, inserted] = owners_.emplace(id, owner);
    if (!inserted)
      throw UsageError("'" + owner + "' and '" + it->second + "' both become the C identifier " +
                       id + " in the header; rename one of them in the sensors file");
  }
  std::string str() const { return out_.str(); }

 private:
  std::ostringstream out_;
  std::map<std::string, std::string> owners_;
};

void writeLinearSensor(HeaderWriter& h, const std::string& name, double gain, double bias,
                       const std::string& unit_suffix, const std::string& unit) {
  const std::string M = "STAC_" + identifier(name, true);
  const std::string f = "stac_" + identifier(name, false);
  const std::string owner = "sensor " + name;
  h.define(M + "_GAIN", number(gain), owner);
  h.define(M + "_BIAS", number(bias), owner);
  h.claim(f + "_to_" + unit_suffix, owner);
  h.claim(f + "_from_" + unit_suffix, owner);
  h.line("/* The " + unit + " a raw reading stands for: (raw - bias) / gain. */");
  h.line("static inline double " + f + "_to_" + unit_suffix + "(double raw) {");
  h.line("  return (raw - " + M + "_BIAS) / " + M + "_GAIN;");
  h.line("}");
  h.line("/* The raw reading expected at a " + unit + ": gain * value + bias. */");
  h.line("static inline double " + f + "_from_" + unit_suffix + "(double value) {");
  h.line("  return " + M + "_GAIN * value + " + M + "_BIAS;");
  h.line("}");
}

std::string header(const stac::RobotModel& robot, const stac::SensorsFile& file,
                   const std::string& sensors_path, const std::string& urdf_path,
                   const std::string& output_path) {
  const stac::SensorSet& s = file.sensors;
  const stac::SensorParameters& theta = file.theta;
  const std::string out_name = fs::path(output_path).filename().string();
  const std::string guard = "STAC_" + identifier(out_name, true);

  HeaderWriter h;
  h.claim(guard, "the include guard");
  h.line("/* " + commentText(out_name) + ": sensor calibration of robot '" +
         commentText(robot.name()) + "' for firmware (C99).");
  h.line(" * Generated by stac_export_header " STAC_VERSION " from " +
         commentText(fs::path(sensors_path).filename().string()) + " and " +
         commentText(fs::path(urdf_path).filename().string()) + ".");
  h.line(" * Do not edit: regenerate it after each calibration.");
  h.line(" *");
  h.line(" *   joint sensor   raw = GAIN * q + BIAS   (q: rad; m on a prismatic joint)");
  h.line(" *   tendon sensor  raw = GAIN * L + BIAS   (L: m)");
  h.line(" *   marker         x_mocap = R (T_link * position) + t, with T_link the");
  h.line(" *                  link's pose in the robot base frame and (R, t) the");
  h.line(" *                  mocap frame: the pose of the robot base in the mocap frame.");
  h.line(" */");
  h.line("#ifndef " + guard);
  h.line("#define " + guard);
  h.line();
  h.define("STAC_NUM_JOINT_SENSORS", std::to_string(s.joint_sensors.size()), "the header");
  h.define("STAC_NUM_TENDON_SENSORS", std::to_string(s.tendon_sensors.size()), "the header");
  h.define("STAC_NUM_MARKERS", std::to_string(s.markers.size()), "the header");

  if (!s.joint_sensors.empty()) {
    h.line();
    h.line("/* ---- Joint sensors: raw = GAIN * q + BIAS ---- */");
  }
  for (std::size_t i = 0; i < s.joint_sensors.size(); ++i) {
    const stac::JointSensorConfig& js = s.joint_sensors[i];
    const stac::GainBias& gb = theta.joint_sensor[i];
    if (gb.gain == 0)
      throw stac::InputError(sensors_path, "joint sensor '" + js.name +
                                               "' has gain 0: its reading cannot be "
                                               "converted to a joint angle");
    const stac::MovableJoint& joint = robot.movableJoints()[js.joint];
    const bool prismatic = joint.type == stac::JointType::kPrismatic;
    const std::string M = "STAC_" + identifier(js.name, true);
    h.line();
    h.line("/* " + commentText(js.name) + " on " + (prismatic ? "prismatic" : "revolute") +
           " joint " + commentText(js.joint_name) + (joint.is_mimic ? " (a mimic follower)" : "") +
           " */");
    h.define(M + "_JOINT", cString(js.joint_name), "sensor " + js.name);
    writeLinearSensor(h, js.name, gb.gain, gb.bias, prismatic ? "metres" : "radians",
                      prismatic ? "joint position (m)" : "joint angle (rad)");
  }

  if (!s.tendon_sensors.empty()) {
    h.line();
    h.line("/* ---- Tendon sensors: raw = GAIN * L + BIAS ---- */");
  }
  for (std::size_t i = 0; i < s.tendon_sensors.size(); ++i) {
    const stac::TendonSensorConfig& ts = s.tendon_sensors[i];
    const stac::GainBias& gb = theta.tendon_sensor[i];
    if (gb.gain == 0)
      throw stac::InputError(sensors_path, "tendon sensor '" + ts.name +
                                               "' has gain 0: its reading cannot be "
                                               "converted to a length");
    const std::string M = "STAC_" + identifier(ts.name, true);
    const std::string owner = "sensor " + ts.name;
    h.line();
    if (ts.kind == stac::TendonSensorConfig::Kind::kCoupling) {
      h.line("/* " + commentText(ts.name) + ": coupling L = sum of COUPLING_<joint> * q_joint */");
      for (const stac::CouplingTerm& term : ts.coupling)
        h.define(M + "_COUPLING_" + identifier(term.joint_name, true), number(term.coefficient),
                 owner);
    } else {
      h.line("/* " + commentText(ts.name) +
             ": path L = length of the polyline through the anchors (m, link frames) */");
      h.define(M + "_NUM_ANCHORS", std::to_string(ts.path.size()), owner);
      for (std::size_t k = 0; k < ts.path.size(); ++k) {
        const std::string A = M + "_ANCHOR_" + std::to_string(k);
        const Eigen::Vector3d& p = ts.path[k].point;
        h.define(A + "_LINK", cString(ts.path[k].link_name), owner);
        h.define(A, "{ " + number(p.x()) + ", " + number(p.y()) + ", " + number(p.z()) + " }",
                 owner);
      }
    }
    writeLinearSensor(h, ts.name, gb.gain, gb.bias, "length", "tendon length (m)");
  }

  if (s.hasMarkers()) {
    const Eigen::Quaterniond& q = theta.mocap.rotation;
    const Eigen::Vector3d& t = theta.mocap.translation;
    h.line();
    h.line("/* ---- Mocap frame: x_mocap = R x_base + t; R as a unit quaternion ---- */");
    h.define("STAC_MOCAP_QW", number(q.w()), "the mocap frame");
    h.define("STAC_MOCAP_QX", number(q.x()), "the mocap frame");
    h.define("STAC_MOCAP_QY", number(q.y()), "the mocap frame");
    h.define("STAC_MOCAP_QZ", number(q.z()), "the mocap frame");
    h.define("STAC_MOCAP_TX", number(t.x()), "the mocap frame");
    h.define("STAC_MOCAP_TY", number(t.y()), "the mocap frame");
    h.define("STAC_MOCAP_TZ", number(t.z()), "the mocap frame");
    h.define("STAC_MOCAP_QUATERNION",
             "{ STAC_MOCAP_QW, STAC_MOCAP_QX, STAC_MOCAP_QY, STAC_MOCAP_QZ }", "the mocap frame");
    h.define("STAC_MOCAP_TRANSLATION", "{ STAC_MOCAP_TX, STAC_MOCAP_TY, STAC_MOCAP_TZ }",
             "the mocap frame");
    h.line();
    h.line("/* ---- Markers: position in the link's frame (m) ---- */");
  }
  for (std::size_t i = 0; i < s.markers.size(); ++i) {
    const stac::MarkerConfig& m = s.markers[i];
    const Eigen::Vector3d& d = theta.marker_position[i];
    const std::string M = "STAC_" + identifier(m.name, true);
    const std::string owner = "marker " + m.name;
    h.line("/* " + commentText(m.name) + " on link " + commentText(m.link_name) + " */");
    h.define(M + "_LINK", cString(m.link_name), owner);
    h.define(M + "_X", number(d.x()), owner);
    h.define(M + "_Y", number(d.y()), owner);
    h.define(M + "_Z", number(d.z()), owner);
    h.define(M + "_POSITION", "{ " + M + "_X, " + M + "_Y, " + M + "_Z }", owner);
  }

  h.line();
  h.line("#endif /* " + guard + " */");
  return h.str();
}

int run(const Args& args) {
  const std::string sensors_path = args.get("sensors");
  const std::string urdf_path = args.get("urdf");
  const std::string output_path = args.get("output");
  stac::cli::checkOutputs({urdf_path, sensors_path}, {{"--output", output_path}});

  const stac::RobotModel robot = stac::RobotModel::fromFile(urdf_path);
  const stac::SensorsFile file = stac::loadSensorsFile(sensors_path, robot);
  stac::cli::writeOutput(output_path,
                         header(robot, file, sensors_path, urdf_path, output_path));
  std::cerr << "stac_export_header: " << file.sensors.joint_sensors.size()
            << " joint sensors, " << file.sensors.tendon_sensors.size() << " tendon sensors, "
            << file.sensors.markers.size() << " markers -> " << output_path << "\n";
  // T_link and path lengths come from the robot's own kinematics: the
  // corrected geometry lives in the URDF, not in this header.
  if (!file.sensors.joint_origins.empty())
    std::cerr << "stac_export_header: note: the " << file.sensors.joint_origins.size()
              << " joint-origin corrections are not in the header; compute T_link with the URDF "
                 "written by stac_calib --urdf-out\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return stac::cli::runApp(argc, argv, "stac_export_header", kSynopsis, kOptions, run);
}
