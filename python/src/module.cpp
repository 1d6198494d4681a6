// The extension module stac._stac; the package `stac` (python/stac)
// re-exports it.
#include "bindings.hpp"

PYBIND11_MODULE(_stac, m) {
  using namespace stac::python;
  m.doc() =
      "STAC — Simultaneous Tracking And Calibration of a robot's kinematic sensors.\n\n"
      "The C++ library's own functions: the same file formats, checks, errors and results "
      "as the stac_calib, stac_simulate and stac_eval commands.";
  bindErrors(m);
  bindRobot(m);
  bindSensors(m);
  bindLog(m);
  bindCalibrate(m);
  bindAnalysis(m);
}
