// The extension module stac._stac; the package `stac` (python/stac)
// re-exports it.
#include "bindings.hpp"

PYBIND11_MODULE(_stac, m) {
  using namespace stac::python;
  m.doc() =
      "STAC — Simultaneous Tracking And Calibration of a robot's kinematic sensors.\n\n"
      "The C++ library's own functions: the same file formats, checks, errors and results "
      "as the stac_calib, stac_simulate and stac_eval commands.";
  // Classes take their __module__ from the module's name when made: "stac",
  // the package users import, so that signatures and reprs say stac.Log.
  const py::object name = m.attr("__name__");
  m.attr("__name__") = "stac";
  bindErrors(m);
  bindRobot(m);
  bindSensors(m);
  bindLog(m);
  bindCalibrate(m);
  bindAnalysis(m);
  m.attr("__name__") = name;
}
