// stac.simulate and stac.evaluate: synthetic logs from a known truth
// (stac_simulate) and cross-sensor prediction on held-out data (stac_eval).
#include <pybind11/stl.h>

#include "bindings.hpp"
#include "stac/evaluate.hpp"
#include "stac/measurement.hpp"
#include "stac/simulate.hpp"

namespace stac::python {

using namespace pybind11::literals;

namespace {

py::dict simulateLogOf(const RobotModel& robot, const Sensors& truth, int frames,
                       std::uint64_t seed, double rate, double noise_scale, double dropout,
                       double outliers) {
  SimulationOptions options;
  options.frames = frames;
  options.seed = seed;
  options.rate_hz = rate;
  options.noise_scale = noise_scale;
  options.dropout = dropout;
  options.outliers = outliers;
  std::string error;
  if (!options.isValid(&error)) throw py::value_error(error);
  Simulation sim;
  {
    py::gil_scoped_release release;
    const MeasurementModel model(robot, truth.file.sensors);
    sim = simulate(model, truth.file.theta, options);
  }
  py::list gross;
  for (const SimulatedOutlier& o : sim.data.outliers)
    gross.append(py::dict("frame"_a = o.frame, "group"_a = groupKey(o.group), "sensor"_a = o.name));
  sim.data.log.path = "<simulated>";
  return py::dict("log"_a = std::make_shared<Log>(std::move(sim.data.log)),
                  "joint_angles"_a = matrixOwned(std::move(sim.q)), "outliers"_a = gross);
}

int groupIndex(const std::string& name, const char* what) {
  if (const std::optional<SensorGroup> g = groupFromName(name)) return static_cast<int>(*g);
  throw py::value_error(std::string(what) + " '" + name + "': must be marker, joint or tendon");
}

// The groups of `names` into flags; each must have sensors and be named once
// (as stac_eval refuses --use/--predict of a group the sensors file lacks,
// or names twice).
void groupFlags(const std::vector<std::string>& names, const Sensors& s, const char* what,
                bool* flags) {
  std::fill(flags, flags + kNumSensorGroups, false);
  for (const std::string& name : names) {
    const int g = groupIndex(name, what);
    if (s.file.sensors.groupSize(static_cast<SensorGroup>(g)) == 0)
      throw py::value_error(std::string(what) + " " + name + ": the sensors file '" + s.source +
                            "' has no " + name + " sensors");
    if (flags[g]) throw py::value_error(std::string(what) + ": names '" + name + "' twice");
    flags[g] = true;
  }
}

py::dict evaluateLog(const RobotModel& robot, const Sensors& sensors, const Log& log,
                     const std::vector<std::string>& use, py::object predict,
                     const Sensors* truth, int threads, const std::string& mocap_units) {
  EvaluationOptions options;
  groupFlags(use, sensors, "use", options.use);
  if (!predict.is_none())
    groupFlags(predict.cast<std::vector<std::string>>(), sensors, "predict", options.predict);
  options.threads = threads;
  if (mocap_units != "m" && mocap_units != "mm")
    throw py::value_error("mocap_units='" + mocap_units + "': must be one of m|mm");
  std::string error;
  if (!options.isValid(&error)) throw py::value_error(error);
  std::vector<ParameterError> truth_errors;
  if (truth)
    truth_errors = compareToTruth(sensors.file.sensors, sensors.file.theta, truth->file.sensors,
                                  truth->file.theta, truth->source);
  EvaluationResult r;
  {
    py::gil_scoped_release release;
    const Observations obs =
        bindLog(log, sensors.file, sensors.source, mocap_units == "mm" ? 1e-3 : 1.0);
    requireReadings(obs, sensors.file.sensors, log.path, ReadingCheck::kAnyFrame);
    r = evaluatePrediction(robot, sensors.file.sensors, sensors.file.theta, obs, options);
  }
  const auto* truth_ptr = truth ? &truth_errors : nullptr;
  // The numbers as stac_eval --json writes them, plus the text and q.
  py::dict d = py::module_::import("json").attr("loads")(evaluationJson(r, truth_ptr));
  d["report"] = evaluationReport(r, truth_ptr);
  d["joint_angles"] = matrixOwned(std::move(r.q));
  return d;
}

}  // namespace

void bindAnalysis(py::module_& m) {
  m.def("simulate", &simulateLogOf, py::arg("robot"), py::arg("truth"), py::arg("frames"),
        py::kw_only(), py::arg("seed") = 1, py::arg("rate") = 100.0,
        py::arg("noise_scale") = 1.0, py::arg("dropout") = 0.0, py::arg("outliers") = 0.0,
        "Synthetic readings of smooth random motion from the `truth` sensors, as "
        "stac_simulate makes them (the same seed gives the same log). Returns "
        "{'log': Log, 'joint_angles': frames x dof array (the true q; owns its data), "
        "'outliers': [{'frame', 'group', 'sensor'}]}.");
  m.def("evaluate", &evaluateLog, py::arg("robot"), py::arg("sensors"), py::arg("log"),
        py::kw_only(), py::arg("use"), py::arg("predict") = py::none(),
        py::arg("truth") = nullptr, py::arg("threads") = 0, py::arg("mocap_units") = "m",
        "Cross-sensor prediction, as stac_eval: q of each frame estimated from the `use` "
        "groups only ('marker', 'joint', 'tendon'), every `predict` group (default: all "
        "present) predicted. Returns stac_eval's --json numbers as a dict ('frames', 'use', "
        "'mae', 'per_sensor', and 'truth' with truth=Sensors), plus 'report' (its text) "
        "and 'joint_angles' (frames x dof, owns its data).");
}

}  // namespace stac::python
