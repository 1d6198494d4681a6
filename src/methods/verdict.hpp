// The tool's own checks of a calibration (SPEC §3 summary.verdict, §4 exit
// 4): a result that fails one is still written, with the reasons, so that a
// wrong minimum is never a silent, confident answer.
#pragma once

#include <string>
#include <vector>

#include "methods/method.hpp"

namespace stac {

// Fitted σ (or, without variance adaptation, residual RMS per reading row)
// over the seed σ beyond which a group is suspect.
constexpr double kSuspectFitRatio = 3.0;
// A sensor whose RMS residual is this many times its own σ (no robust loss).
constexpr double kSuspectSensorRatio = 4.0;

// The frames a method fitted (all of the log's, or the classical
// regression's usable ones) and their q.
struct Fit {
  const Observations& obs;
  const RowMatrix& q;
};

// The reasons r fails the checks (empty: ok). `in` is the run's input, `out`
// its outcome (for the EKF's costs), `fit` what r's statistics are over; r
// has its summary and statistics.
std::vector<std::string> verdictOf(const MethodInput& in, const Outcome& out, const Fit& fit,
                                   const CalibrationResult& r);

}  // namespace stac
