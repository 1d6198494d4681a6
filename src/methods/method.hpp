// The calibration methods behind calibrate() (paper §II-C, §IV): the STAC
// alternation, the monolithic problem, the EKF and the classical regression.
// Each takes the immutable Problem and the seed and hands back an Outcome;
// calibrate() alone turns an Outcome into a CalibrationResult (result.cpp),
// so every method's result means the same thing.
#pragma once

#include <chrono>
#include <optional>
#include <string>
#include <vector>

#include "methods/mirror_ambiguity.hpp"
#include "solve/problem.hpp"
#include "solve/uncertainty.hpp"
#include "stac/calibrate.hpp"

namespace stac {

struct Outcome {
  SensorParameters theta;
  NoiseModel noise;            // final σ per sensor
  double marker_scale = 1.0;   // the marker group's κ (scales mocap.sigma)
  RowMatrix q;                 // per frame of the log (NaN where undefined)
  // The frames the fit used (empty: all) and, per joint sensor, whether it
  // defines its joint's angle (σ_p -> 0: no residual, no σ to report).
  std::vector<int> fitted_frames;
  std::vector<bool> defining_joint;
  int iterations = 0;
  bool converged = false;
  double initial_cost = 0, final_cost = 0;
  double before_rms[kNumSensorGroups] = {0, 0, 0};
  double after_rms[kNumSensorGroups] = {0, 0, 0};  // PassStats::rms of the final pass
  UncertaintyResult uncertainty;
  // A Huber run that set gross readings aside: the verdict reason when a
  // run with Cauchy's loss disagrees (redescending_check.hpp); else empty.
  std::string loss_disagreement;
  // A run that converged only after a crawl, still misfitting: the
  // verdict reason (alternation.cpp slowConvergence); else empty.
  std::string slow_convergence;
  // The mirrors' candidates, where the run found them at theta and q on
  // the whole log with the final σ (alternation.cpp takeBetterEquivalent);
  // else makeResult finds them.
  std::optional<MirrorCandidates> mirrors;
};

using Clock = std::chrono::steady_clock;

// What every method is given: the problem, the seed and the options
// (CalibrationOptions::isValid() passed), the start of the run for the
// progress reports, and q0 (frames x dof) or nullptr.
struct MethodInput {
  const Problem& problem;
  const SensorParameters& seed;
  const CalibrationOptions& options;
  Clock::time_point start;
  const RowMatrix* q0 = nullptr;
};

Outcome runStac(const MethodInput& in);         // stac.cpp (also Method::kMonolithic's start)
Outcome runMonolithic(const MethodInput& in);   // monolithic.cpp
Outcome runEkf(const MethodInput& in);          // ekf.cpp
Outcome runClassical(const MethodInput& in);    // classical.cpp

// The result of a run (the only place one is built).
CalibrationResult makeResult(const MethodInput& in, Outcome&& outcome, RowMatrix* joint_angles);

}  // namespace stac
