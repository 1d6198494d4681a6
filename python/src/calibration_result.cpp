// stac.CalibrationResult: properties that build plain Python objects (dicts,
// lists, floats, new small arrays) from the result on each access, and the
// joint angles as a view of the result's own matrix.
#include "calibration_result.hpp"

#include <pybind11/stl.h>

#include "stac/file_io.hpp"
#include "stac/sensors_file.hpp"

namespace stac::python {

using namespace pybind11::literals;

const char* const kCalibrateDoc = R"(Calibrates the sensors from the log, as stac_calib does.

The same run as `stac_calib --urdf ... --sensors ... --log ...` with the same
options: the wide-basin start, the same checks of the inputs (the same
errors, naming the same files and lines) and the same result:
write_sensors(path, result) writes the bytes stac_calib --output writes
(the summary's wall_time aside, which is measured).

method: 'stac' (alternation, default), 'joint' (one monolithic problem),
'ekf' or 'classical' (the paper's baselines). q_phase: 'lm-iter',
'lm-batch' or 'bfgs'. threads: 0 = all cores. loss: 'none', 'huber' or
'cauchy', loss_scale in σ. mocap_units: 'm' or 'mm'. ekf_*: the EKF's
options (method='ekf' only): ekf_initial_q (q of the first frame, dof
values), ekf_q_speed, ekf_iterations, ekf_theta_std.

progress: a callable given one dict per iteration: {'iteration': int,
'stage': str ('init', 'seed', 'stac', 'joint', 'ekf', 'classical'),
'cost': float, 'rms': {group: float}, 'elapsed': seconds}. An exception
it raises stops the calibration and propagates from calibrate(); so does
Ctrl-C (KeyboardInterrupt), checked at each iteration.

The GIL is released while the library works. Raises InputError for bad
input, ValueError for bad options, and warns with
SuspectCalibrationWarning when the result fails its own checks
(result.verdict lists why; stac_calib exits 4).)";

namespace {

py::dict stdDict(const CalibrationResult& r) {
  py::dict mocap, markers, joints, tendons;
  const SensorSet& s = r.sensors;
  if (s.hasMarkers()) {
    mocap["translation"] = vector3(r.std.mocap_translation);
    mocap["rotation"] = vector3(r.std.mocap_rotation);
  }
  for (size_t i = 0; i < s.markers.size() && i < r.std.marker_position.size(); ++i)
    markers[py::str(s.markers[i].name)] = vector3(r.std.marker_position[i]);
  for (size_t i = 0; i < s.joint_sensors.size() && i < r.std.joint_sensor.size(); ++i)
    joints[py::str(s.joint_sensors[i].name)] = gainBiasDict(r.std.joint_sensor[i]);
  for (size_t i = 0; i < s.tendon_sensors.size() && i < r.std.tendon_sensor.size(); ++i)
    tendons[py::str(s.tendon_sensors[i].name)] = gainBiasDict(r.std.tendon_sensor[i]);
  return py::dict("mocap"_a = mocap, "markers"_a = markers, "joint_sensors"_a = joints,
                  "tendon_sensors"_a = tendons,
                  "joint_origins"_a = originsDict(s, r.std.joint_origin));
}

template <class Config>
py::dict residualsOf(const std::vector<Config>& configs, const std::vector<ResidualStats>& stats) {
  py::dict d;
  for (size_t i = 0; i < configs.size() && i < stats.size(); ++i)
    d[py::str(configs[i].name)] =
        py::dict("rms"_a = stats[i].rms, "mae"_a = stats[i].mae, "count"_a = stats[i].count);
  return d;
}

py::dict residualsDict(const CalibrationResult& r) {
  return py::dict("markers"_a = residualsOf(r.sensors.markers, r.marker_residual),
                  "joint_sensors"_a = residualsOf(r.sensors.joint_sensors, r.joint_residual),
                  "tendon_sensors"_a = residualsOf(r.sensors.tendon_sensors, r.tendon_residual));
}

py::dict perGroup(const CalibrationSummary& s, const double* values) {
  py::dict d;
  for (int g = 0; g < kNumSensorGroups; ++g)
    if (s.group_present[g]) d[groupKey(static_cast<SensorGroup>(g))] = values[g];
  return d;
}

py::list unidentifiableList(const CalibrationSummary& s) {
  py::list l;
  for (const UnidentifiableDirection& d : s.unidentifiable)
    l.append(py::dict("parameters"_a = d.parameters, "reason"_a = d.reason,
                      "kind"_a = undeterminedName(d.kind)));
  return l;
}

py::list originsList(const CalibrationSummary& s) {
  py::list l;
  for (const OriginDetermination& d : s.origins)
    l.append(py::dict("joint"_a = d.joint, "determined"_a = d.determined,
                      "on_prior"_a = d.on_prior));
  return l;
}

py::dict summaryDict(const CalibrationSummary& s) {
  py::list downweighted;
  for (const DownweightedReading& d : s.downweighted)
    downweighted.append(py::dict("frame"_a = d.frame, "sensor"_a = d.sensor, "weight"_a = d.weight));
  return py::dict("method"_a = s.method, "q_phase"_a = s.q_phase, "iterations"_a = s.iterations,
                  "converged"_a = s.converged, "initial_cost"_a = s.initial_cost,
                  "final_cost"_a = s.final_cost, "frames"_a = s.frames,
                  "wall_time"_a = s.wall_time, "sigma"_a = perGroup(s, s.group_sigma),
                  "rms_before"_a = perGroup(s, s.before_rms),
                  "rms_after"_a = perGroup(s, s.after_rms),
                  "unidentifiable"_a = unidentifiableList(s), "downweighted"_a = downweighted,
                  "joint_origins"_a = originsList(s),
                  "spikes_set_aside"_a = py::dict("marker"_a = s.spikes_set_aside[0],
                                                  "joint"_a = s.spikes_set_aside[1],
                                                  "tendon"_a = s.spikes_set_aside[2]),
                  "verdict"_a = s.verdict);
}

std::string yamlOf(const Calibration& c) {
  return sensorsToYaml(c.result.sensors, c.result.theta, &c.result);
}

}  // namespace

void warnIfSuspect(const CalibrationSummary& summary) {
  if (!summary.suspect()) return;
  // Kept for the process's life (a static py::object would be released after
  // the interpreter is gone).
  static PyObject* const category =
      py::object(py::module_::import("stac._stac").attr("SuspectCalibrationWarning")).release().ptr();
  std::string message = "the calibration failed its own checks (result.verdict):";
  for (const std::string& reason : summary.verdict) message += "\n  " + reason;
  if (PyErr_WarnEx(category, message.c_str(), 2) != 0) throw py::error_already_set();
}

void bindCalibrationResult(py::module_& m) {
  m.attr("SuspectCalibrationWarning") = py::handle(PyErr_NewExceptionWithDoc(
      "stac.SuspectCalibrationWarning",
      "The calibration failed its own checks: result.verdict says why.", PyExc_UserWarning,
      nullptr));
  py::class_<Calibration>(m, "CalibrationResult", "What stac.calibrate returns.")
      .def_property_readonly(
          "parameters", [](const Calibration& c) { return parametersDict(c.result.sensors, c.result.theta); },
          "The calibrated θ, shaped as Sensors.parameters.")
      .def_property_readonly("std", [](const Calibration& c) { return stdDict(c.result); },
                             "One standard deviation per parameter (inf: the data cannot "
                             "determine it; 0: fixed): {'mocap': {'translation', 'rotation'}, "
                             "'markers': {name: xyz}, 'joint_sensors': {name: {'gain', "
                             "'bias'}}, 'tendon_sensors': {...}}.")
      .def_property_readonly("sigma", [](const Calibration& c) { return sigmaDict(c.result.sensors); },
                             "The final σ of each sensor and marker, by name.")
      .def_property_readonly("residuals", [](const Calibration& c) { return residualsDict(c.result); },
                             "Per sensor and marker: {'rms', 'mae', 'count'} (raw units; "
                             "markers: Euclidean distance, m), under 'markers', "
                             "'joint_sensors', 'tendon_sensors'.")
      .def_property_readonly(
          "joint_angles",
          [](py::object self) { return matrixView(self.cast<const Calibration&>().q, self); },
          "Final q of every frame: frames x dof float64, a read-only view of the result's own "
          "matrix (no copy). Columns in RobotModel.joint_names order.")
      .def_property_readonly("summary", [](const Calibration& c) { return summaryDict(c.result.summary); },
                             "The YAML's summary as a dict (method, iterations, converged, "
                             "costs, frames, wall_time, per-group sigma and rms_before/after, "
                             "unidentifiable, downweighted, verdict).")
      .def_property_readonly("verdict", [](const Calibration& c) { return c.result.summary.verdict; },
                             "Why the result failed its own checks; [] when it passed ('ok').")
      .def_property_readonly("ok", [](const Calibration& c) { return !c.result.summary.suspect(); })
      .def_property_readonly("unidentifiable",
                             [](const Calibration& c) { return unidentifiableList(c.result.summary); },
                             "Parameter sets the data cannot determine: [{'parameters': [...], "
                             "'reason': str}].")
      .def_property_readonly(
          "sensors",
          [](const Calibration& c) {
            return Sensors{SensorsFile{c.result.sensors, c.result.theta, {}}, c.source};
          },
          "The calibrated sensors (final θ and σ), e.g. as the next seed or for evaluate().")
      .def_readonly("report", &Calibration::report, "The summary stac_calib prints.")
      .def("to_yaml", &yamlOf, "The calibration file's text (what write_sensors writes).")
      .def("__repr__", [](const Calibration& c) {
        const CalibrationSummary& s = c.result.summary;
        return "<stac.CalibrationResult " + s.method + ": " + std::to_string(s.iterations) +
               " iterations, " + (s.suspect() ? "suspect" : "ok") + ">";
      });
  m.def(
      "write_sensors", [](const Path& path, const Calibration& c) { writeText(path.string(), yamlOf(c)); },
      py::arg("path"), py::arg("result"));
}

}  // namespace stac::python
