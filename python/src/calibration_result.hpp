// stac.CalibrationResult: what stac.calibrate returns, the library's
// CalibrationResult and joint angles seen as plain Python and numpy objects.
#pragma once

#include <string>

#include "bindings.hpp"
#include "stac/calibration.hpp"

namespace stac::python {

struct Calibration {
  CalibrationResult result;
  RowMatrix q;            // frames x dof, the final joint angles
  std::string source;     // the seed's source: the calibrated sensors keep it
  std::string report;     // briefReport(): what stac_calib prints
};

void bindCalibrationResult(py::module_& m);

// Warns with stac.SuspectCalibrationWarning when the result failed its own
// checks (where stac_calib exits 4 and says so on stderr).
void warnIfSuspect(const CalibrationSummary& summary);

extern const char* const kCalibrateDoc;

}  // namespace stac::python
