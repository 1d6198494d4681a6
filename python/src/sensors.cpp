// stac.Sensors and the sensors file (SPEC §3): read, parse, infer from a log
// header, write; the parameters as plain Python objects.
#include <pybind11/stl.h>

#include "bindings.hpp"
#include "io/rpy.hpp"
#include "stac/error.hpp"
#include "stac/file_io.hpp"

using namespace pybind11::literals;

namespace stac::python {

py::dict gainBiasDict(const GainBias& gb) {
  py::dict d;
  d["gain"] = gb.gain;
  d["bias"] = gb.bias;
  return d;
}

py::dict originsDict(const SensorSet& sensors, const std::vector<OriginCorrection>& values) {
  py::dict d;
  for (size_t c = 0; c < sensors.joint_origins.size() && c < values.size(); ++c)
    d[py::str(sensors.joint_origins[c].joint_name)] =
        py::dict("xyz"_a = vector3(values[c].xyz), "rpy"_a = vector3(values[c].rpy));
  return d;
}

py::dict parametersDict(const SensorSet& sensors, const SensorParameters& theta) {
  py::dict mocap, markers, joints, tendons;
  if (sensors.hasMarkers()) {
    const Eigen::Quaterniond& r = theta.mocap.rotation;
    mocap["translation"] = vector3(theta.mocap.translation);
    mocap["rpy"] = vector3(toRpy(r));
    mocap["quaternion"] = vectorCopy(Eigen::Vector4d(r.w(), r.x(), r.y(), r.z()));
  }
  for (size_t i = 0; i < sensors.markers.size(); ++i)
    markers[py::str(sensors.markers[i].name)] = vector3(theta.marker_position[i]);
  for (size_t i = 0; i < sensors.joint_sensors.size(); ++i)
    joints[py::str(sensors.joint_sensors[i].name)] = gainBiasDict(theta.joint_sensor[i]);
  for (size_t i = 0; i < sensors.tendon_sensors.size(); ++i)
    tendons[py::str(sensors.tendon_sensors[i].name)] = gainBiasDict(theta.tendon_sensor[i]);
  py::dict d;
  d["mocap"] = mocap;
  d["markers"] = markers;
  d["joint_sensors"] = joints;
  d["tendon_sensors"] = tendons;
  d["joint_origins"] = originsDict(sensors, theta.joint_origin);
  return d;
}

py::dict sigmaDict(const SensorSet& sensors) {
  py::dict d;
  for (const MarkerConfig& c : sensors.markers) d[py::str(c.name)] = c.sigma;
  for (const JointSensorConfig& c : sensors.joint_sensors) d[py::str(c.name)] = c.sigma;
  for (const TendonSensorConfig& c : sensors.tendon_sensors) d[py::str(c.name)] = c.sigma;
  return d;
}

void writeText(const std::string& path, const std::string& text) {
  try {
    writeFileAtomically(path, text);
  } catch (const std::runtime_error& e) {
    // As stac_calib reports an output it cannot write: bad input, nothing partial left.
    throw InputError(path, std::string("cannot write: ") + e.what());
  }
}

namespace {
template <class Config>
std::vector<std::string> names(const std::vector<Config>& configs) {
  std::vector<std::string> out;
  for (const Config& c : configs) out.push_back(c.name);
  return out;
}
}  // namespace

void bindSensors(py::module_& m) {
  py::class_<Sensors>(m, "Sensors",
                      "A robot's sensors and their parameters θ: a seed, or a calibration read "
                      "back (SPEC §3). Made by read_sensors, parse_sensors, infer_sensors or "
                      "CalibrationResult.sensors.")
      .def_readonly("source", &Sensors::source,
                    "The file (or log) the sensors came from: errors about them name it.")
      .def_property_readonly("markers", [](const Sensors& s) { return names(s.file.sensors.markers); },
                             "Marker names, in file order.")
      .def_property_readonly("joint_sensors",
                             [](const Sensors& s) { return names(s.file.sensors.joint_sensors); },
                             "Joint sensor names, in file order.")
      .def_property_readonly("tendon_sensors",
                             [](const Sensors& s) { return names(s.file.sensors.tendon_sensors); },
                             "Tendon sensor names, in file order.")
      .def_property_readonly(
          "parameters", [](const Sensors& s) { return parametersDict(s.file.sensors, s.file.theta); },
          "θ as a new dict: {'mocap': {'translation', 'rpy', 'quaternion' [w, x, y, z]}, "
          "'markers': {name: position}, 'joint_sensors': {name: {'gain', 'bias'}}, "
          "'tendon_sensors': {...}}; vectors are new float64 arrays.")
      .def_property_readonly("sigma", [](const Sensors& s) { return sigmaDict(s.file.sensors); },
                             "σ of each sensor and marker, by name.")
      .def("to_yaml",
           [](const Sensors& s) { return sensorsToYaml(s.file.sensors, s.file.theta); },
           "The sensors file's text, as write_sensors writes it.")
      .def("__repr__", [](const Sensors& s) {
        const SensorSet& set = s.file.sensors;
        return "<stac.Sensors from " + s.source + ": " + std::to_string(set.markers.size()) +
               " markers, " + std::to_string(set.joint_sensors.size()) + " joint sensors, " +
               std::to_string(set.tendon_sensors.size()) + " tendon sensors>";
      });

  m.def(
      "read_sensors",
      [](const Path& path, const RobotModel& robot) {
        return Sensors{loadSensorsFile(path.string(), robot), path.string()};
      },
      py::arg("path"), py::arg("robot"),
      "Reads a sensors file (a seed or a calibration output) against the robot's links and "
      "joints. Raises InputError naming the file, key and line.");
  m.def(
      "parse_sensors",
      [](const std::string& text, const RobotModel& robot, const std::string& source) {
        return Sensors{parseSensorsYaml(text, source, robot), source};
      },
      py::arg("text"), py::arg("robot"), py::arg("source") = "<string>",
      "Parses sensors-file text; `source` names it in errors.");
  m.def(
      "infer_sensors",
      [](const Log& log, const RobotModel& robot) {
        return Sensors{inferSensorsFromLog(log, robot), log.path};
      },
      py::arg("log"), py::arg("robot"),
      "The sensors a log header implies (SPEC §3 'Without a sensors file'), as stac_calib "
      "without --sensors.");
  m.def(
      "write_sensors",
      [](const Path& path, const Sensors& s) {
        writeText(path.string(), sensorsToYaml(s.file.sensors, s.file.theta));
      },
      py::arg("path"), py::arg("sensors"),
      "Writes a sensors file (or, given a CalibrationResult, the calibration exactly as "
      "stac_calib --output writes it) through a temporary file renamed into place.");
}

}  // namespace stac::python
