// stac.calibrate: what stac_calib does with a robot, a sensors file and a
// log (the wide-basin start, the same checks and errors, the same output),
// with the GIL released while the library works and a progress callback
// that also lets Ctrl-C stop the run.
#include <pybind11/stl.h>

#include <optional>

#include "bindings.hpp"
#include "calibration_result.hpp"
#include "stac/calibrate.hpp"
#include "stac/error.hpp"

namespace stac::python {

namespace {

// Thrown through the library from the progress callback: the library's
// contract is that an exception from options.progress leaves calibrate().
struct Interrupted {};

// options.progress and options.should_stop for calibrate(): the library
// calls both on the calling thread, without the GIL (progress once per
// iteration, should_stop also after every Ceres iteration, as for
// stac_calib's Ctrl-C). Each takes the GIL; progress calls the Python
// callback (if any), should_stop runs the pending signal handlers. A Python
// exception from either (KeyboardInterrupt for Ctrl-C) is kept and the run
// unwound, to be raised once calibrate() has returned and the GIL is back.
class ProgressBridge {
 public:
  explicit ProgressBridge(py::object callback) : callback_(std::move(callback)) {}

  void operator()(const IterationReport& r) {
    if (callback_.is_none()) return;
    py::gil_scoped_acquire gil;
    try {
      callback_(reportDict(r));
    } catch (py::error_already_set& e) {
      error_ = std::move(e);
      throw Interrupted();
    }
  }

  bool stopRequested() {
    py::gil_scoped_acquire gil;
    if (PyErr_CheckSignals() == 0) return false;
    error_ = py::error_already_set();
    return true;
  }

  [[noreturn]] void raise() { throw *error_; }

 private:
  static py::dict reportDict(const IterationReport& r) {
    py::dict rms;
    for (int g = 0; g < kNumSensorGroups; ++g)
      if (r.present[g]) rms[groupKey(static_cast<SensorGroup>(g))] = r.rms[g];
    py::dict d;
    d["iteration"] = r.iteration;
    d["stage"] = r.stage;
    d["cost"] = r.cost;
    d["rms"] = rms;
    d["elapsed"] = r.elapsed;
    return d;
  }

  py::object callback_;
  std::optional<py::error_already_set> error_;
};

template <class T>
T choice(const std::string& name, const std::string& value,
         const std::vector<std::pair<std::string, T>>& choices) {
  std::string list;
  for (const auto& [key, v] : choices) {
    if (key == value) return v;
    list += (list.empty() ? "" : "|") + key;
  }
  throw py::value_error(name + "='" + value + "': must be one of " + list);
}

struct EkfArgs {
  py::object initial_q, q_speed, iterations, theta_std;
};

// The EKF's own options (refused with another method, as stac_calib refuses
// --ekf-* without --method ekf).
void ekfOptions(const EkfArgs& a, const RobotModel& robot, CalibrationOptions* o) {
  const std::pair<const char*, const py::object*> given[] = {
      {"ekf_initial_q", &a.initial_q}, {"ekf_q_speed", &a.q_speed},
      {"ekf_iterations", &a.iterations}, {"ekf_theta_std", &a.theta_std}};
  for (const auto& [name, value] : given)
    if (!value->is_none() && o->method != Method::kEkf)
      throw py::value_error(std::string(name) + " needs method='ekf'");
  if (!a.q_speed.is_none()) o->ekf.q_speed = a.q_speed.cast<double>();
  if (!a.iterations.is_none()) o->ekf.iterations = a.iterations.cast<int>();
  if (!a.theta_std.is_none()) o->ekf.theta_std_scale = a.theta_std.cast<double>();
  if (a.initial_q.is_none()) return;
  const auto q = py::array_t<double, py::array::forcecast>::ensure(a.initial_q);
  if (!q || q.ndim() != 1 || q.shape(0) != robot.dof())
    throw py::value_error("ekf_initial_q: expected " + std::to_string(robot.dof()) +
                          " joint angles (one per joint of q)");
  o->ekf.initial_q = Eigen::Map<const Eigen::VectorXd>(q.data(), q.shape(0));
}

py::object calibrateLog(const RobotModel& robot, const Sensors& sensors, const Log& log,
                        const std::string& method, const std::string& q_phase,
                        int max_iterations, double tolerance, int threads,
                        const std::string& loss, double loss_scale, bool adapt_variance,
                        const std::string& mocap_units, py::object progress,
                        py::object ekf_initial_q, py::object ekf_q_speed,
                        py::object ekf_iterations, py::object ekf_theta_std) {
  CalibrationOptions options;
  options.method = choice<Method>("method", method,
                                  {{"stac", Method::kStac}, {"joint", Method::kMonolithic},
                                   {"ekf", Method::kEkf}, {"classical", Method::kClassical}});
  options.stac.q_phase = choice<QPhaseMethod>(
      "q_phase", q_phase,
      {{"lm-iter", QPhaseMethod::kLmIter}, {"lm-batch", QPhaseMethod::kLmBatch},
       {"bfgs", QPhaseMethod::kBfgs}});
  options.loss = choice<LossKind>(
      "loss", loss,
      {{"none", LossKind::kNone}, {"huber", LossKind::kHuber}, {"cauchy", LossKind::kCauchy}});
  const double mocap_scale = choice<double>("mocap_units", mocap_units, {{"m", 1.0}, {"mm", 1e-3}});
  options.max_iterations = max_iterations;
  options.tolerance = tolerance;
  options.threads = threads;
  options.loss_scale = loss_scale;
  options.adapt_variance = adapt_variance;
  ekfOptions({ekf_initial_q, ekf_q_speed, ekf_iterations, ekf_theta_std}, robot, &options);
  std::string error;
  if (!options.isValid(&error)) throw py::value_error(error);
  if (!progress.is_none() && !PyCallable_Check(progress.ptr()))
    throw py::type_error("progress: expected a callable taking one dict, or None");

  ProgressBridge bridge(std::move(progress));
  options.progress = [&bridge](const IterationReport& r) { bridge(r); };
  options.should_stop = [&bridge] { return bridge.stopRequested(); };
  auto out = std::make_unique<Calibration>();
  try {
    py::gil_scoped_release release;
    const Observations obs = bindLog(log, sensors.file, sensors.source, mocap_scale);
    requireReadings(obs, sensors.file.sensors, log.path, ReadingCheck::kEverySensor);
    out->result = calibrateFromSource(sensors.source, robot, sensors.file.sensors,
                                      sensors.file.theta, obs, options, &out->q);
  } catch (const Interrupted&) {
    bridge.raise();
  } catch (const Cancelled&) {
    bridge.raise();
  }
  out->source = sensors.source;
  out->report = briefReport(robot, sensors.file.theta, out->result);
  warnIfSuspect(out->result.summary);
  return py::cast(std::move(out));
}

}  // namespace

void bindCalibrate(py::module_& m) {
  bindCalibrationResult(m);
  m.def("calibrate", &calibrateLog, py::arg("robot"), py::arg("sensors"), py::arg("log"),
        py::kw_only(), py::arg("method") = "stac", py::arg("q_phase") = "lm-iter",
        py::arg("max_iterations") = 200, py::arg("tolerance") = 1e-7, py::arg("threads") = 0,
        py::arg("loss") = "none", py::arg("loss_scale") = 3.0, py::arg("adapt_variance") = true,
        py::arg("mocap_units") = "m", py::arg("progress") = py::none(),
        py::arg("ekf_initial_q") = py::none(), py::arg("ekf_q_speed") = py::none(),
        py::arg("ekf_iterations") = py::none(), py::arg("ekf_theta_std") = py::none(),
        kCalibrateDoc);
}

}  // namespace stac::python
