// stac_calib --report: one self-contained HTML file (inline CSS and SVG, no
// scripts, no network) that a robotics engineer reads after a calibration.
//
// Sections, each an element with an id: "summary", "convergence" (cost and
// per-group RMS per outer iteration), "residuals" (per-group histograms of
// |residual| before and after), "sensors" (per-sensor RMS table), "markers"
// (seed and calibrated marker positions drawn on the robot's links at the
// neutral pose: views xy, xz, yz) and "unidentifiable". The document is
// well-formed XML (XHTML-compatible), so tests can parse it.
#pragma once

#include <string>
#include <vector>

#include "stac/calibrate.hpp"
#include "stac/calibration.hpp"
#include "stac/residuals.hpp"
#include "stac/robot_model.hpp"
#include "stac/sensors.hpp"

namespace stac::cli {

struct ReportInputs {
  std::string urdf, log, sensors;  // file names as given ("" for inferred)
};

std::string calibrationReportHtml(const RobotModel& robot, const SensorSet& sensors,
                                  const SensorParameters& seed, const CalibrationResult& result,
                                  const std::vector<IterationReport>& history,
                                  const ResidualSample& before, const ResidualSample& after,
                                  const ReportInputs& inputs);

}  // namespace stac::cli
