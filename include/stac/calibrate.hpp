// Calibration: STAC alternation (paper §II-C) or one monolithic problem,
// and the paper's two baselines: an EKF (§IV-A, ekf.hpp) and the classical
// regression with σ_p -> 0 (§IV-B, classical.hpp).
//
//   CalibrationOptions options;            // validated by isValid()
//   CalibrationResult r = calibrate(robot, sensors, seed, observations,
//                                   options, &joint_angles);
//
// The library never prints: progress goes to options.progress, a callback.
#pragma once

#include <functional>
#include <string>

#include "stac/calibration.hpp"
#include "stac/ekf.hpp"
#include "stac/log.hpp"
#include "stac/measurement.hpp"
#include "stac/q_phase.hpp"
#include "stac/robot_model.hpp"
#include "stac/sensors.hpp"

namespace stac {

enum class Method { kStac, kJoint, kEkf, kClassical };

struct IterationReport {
  int iteration = 0;
  double cost = 0.0;                         // ½ Σ ρ at the current σ
  double rms[kNumSensorGroups] = {0, 0, 0};  // raw units (metres, volts...)
  bool present[kNumSensorGroups] = {false, false, false};
  double elapsed = 0.0;                      // seconds since the start
  // The current θ (STAC and joint stages), valid during the callback only:
  // lets experiments trace the parameter error per iteration.
  const SensorParameters* theta = nullptr;
  std::string stage;  // "init", "stac", "joint", "ekf" (per ~10% of frames), "classical"
};

struct CalibrationOptions {
  Method method = Method::kStac;
  QPhaseMethod q_phase = QPhaseMethod::kLmIter;
  int max_iterations = 200;
  double tolerance = 1e-7;     // stop when the relative cost decrease is below
  int threads = 0;             // 0: all cores
  LossKind loss = LossKind::kNone;
  double loss_scale = 3.0;     // in units of σ
  bool adapt_variance = true;
  bool wide_basin_init = true; // marker-first initialisation (see calibrate.cpp)
  bool coupled_steps = true;  // finish with coupled (q, θ) steps (schur.hpp)
  int max_downweighted = 20;   // readings listed in the summary
  EkfOptions ekf;              // Method::kEkf only
  std::function<void(const IterationReport&)> progress;

  bool isValid(std::string* error) const;
};

// q0: initial joint angles (frames x dof), or nullptr for the neutral pose
// (0 clamped into the limits) in every frame (the EKF uses its first row
// unless options.ekf.initial_q is set; the classical regression ignores it).
// joint_angles (optional) receives the final q_t.
CalibrationResult calibrate(const RobotModel& robot, const SensorSet& sensors,
                            const SensorParameters& seed, const Observations& obs,
                            const CalibrationOptions& options,
                            RowMatrix* joint_angles = nullptr,
                            const RowMatrix* q0 = nullptr);

// RMS residual per group in raw units with θ held fixed and each q_t fitted
// to it (a few LM steps from q_start, frames x dof), on at most 1000 frames
// spread over the log: the summary's "before".
void fittedResidualRms(const MeasurementModel& model, const SensorParameters& theta,
                       const NoiseModel& noise, const RobustLoss& loss, const Observations& obs,
                       const RowMatrix& q_start, int threads, double rms[kNumSensorGroups]);

// The summary's per-group σ (RMS over the group's sensors; in the joint
// group, over those with !(*skip_joint)[i] when skip_joint is given, 0 if
// none) and which groups the sensors have.
void summariseGroupNoise(const SensorSet& sensors, const NoiseModel& noise,
                         CalibrationSummary* summary,
                         const std::vector<bool>* skip_joint = nullptr);

// Per-sensor residual statistics in raw units at the given q and θ.
void residualStatistics(const MeasurementModel& model, const SensorParameters& theta,
                        const Observations& obs, const RowMatrix& q, int threads,
                        CalibrationResult* result);

// The neutral pose: 0 clamped into each joint's limits.
Eigen::VectorXd neutralPose(const RobotModel& robot);

}  // namespace stac
