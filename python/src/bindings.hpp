// The Python module `stac._stac` (pybind11): one bind*() per concept, each in
// its own file, and the few types the module adds around the library's.
//
// The module is a front end like the apps: it parses Python arguments, calls
// the library and converts the results; it computes nothing of its own.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl/filesystem.h>

#include <filesystem>

#include <string>

#include "stac/log.hpp"
#include "stac/robot_model.hpp"
#include "stac/sensors_file.hpp"

namespace stac::python {

namespace py = pybind11;

// File names: a str or any os.PathLike (pathlib.Path).
using Path = std::filesystem::path;

// A sensors file as read, with where it came from: calibrate() names that
// source in errors about the sensors (as stac_calib names its --sensors, or
// the log the sensors were inferred from).
struct Sensors {
  SensorsFile file;
  std::string source;
};

void bindErrors(py::module_& m);
void bindRobot(py::module_& m);
void bindSensors(py::module_& m);
void bindLog(py::module_& m);
void bindCalibrate(py::module_& m);
void bindAnalysis(py::module_& m);

// Numpy arrays over memory that `owner` keeps alive: no copy. Read-only,
// because the library's objects are immutable once made.
py::array_t<double> matrixView(const RowMatrix& m, py::handle owner);
py::array_t<double> vectorView(const std::vector<double>& v, py::handle owner);
// A matrix the library returned, moved under a new array: no copy.
py::array_t<double> matrixOwned(RowMatrix&& m);
// Copies (small, or computed on the fly): a new array that owns its data.
py::array_t<double> vectorCopy(const Eigen::VectorXd& v);
py::array_t<double> vector3(const Eigen::Vector3d& v);

// A 2-D array-like as a float64 C-contiguous frames x columns matrix: a view
// of it when it is one already, else of the converted copy that `array`
// holds. `what` names the argument in errors.
struct MatrixIn {
  py::array_t<double> array;
  Eigen::Map<const RowMatrix> matrix;
};
MatrixIn matrixFrom(const py::handle& array, const char* what);

// Shared by the sensors and the result: θ, σ and a gain/bias as dicts, and
// a text file written as stac_calib writes its outputs (InputError if not).
py::dict gainBiasDict(const GainBias& gb);
py::dict parametersDict(const SensorSet& sensors, const SensorParameters& theta);
// Per corrected joint {xyz, rpy}: the corrections, or their std.
py::dict originsDict(const SensorSet& sensors, const std::vector<OriginCorrection>& values);
py::dict sigmaDict(const SensorSet& sensors);
void writeText(const std::string& path, const std::string& text);

// The sensor group's name, as in the YAML ("marker", "joint", "tendon").
py::str groupKey(SensorGroup g);

}  // namespace stac::python
