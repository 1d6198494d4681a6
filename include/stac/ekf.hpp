// Extended Kalman filter baseline (paper §IV-A, eq. 24-27; --method ekf).
//
// State [θ; q]: the free entries of θ in MeasurementModel order (the mocap
// rotation as a 3-vector error state: R <- exp([δ]x) R, its covariance in
// that tangent space) followed by the joint angles. Dynamics (eq. 24): θ
// constant, q a random walk with covariance Σ_q per frame. Observations
// (eq. 25-27): every reading of the frame through evaluateFrame(), i.e. the
// same sensor models and Jacobians as STAC, whitened by the seed σ. One
// forward pass over the frames; missing readings are skipped; q is clamped to
// the joint limits widened by 5% of the range, as in the q-phase.
//
// The paper (§VI-B) starts q_0 at the truth of the first frame; without a
// given q_0 we solve frame 0 for q with the seed θ (Levenberg-Marquardt from
// the neutral pose), which is all a filter started from the seed can do.
#pragma once

#include <Eigen/Core>
#include <string>

#include "stac/calibration.hpp"
#include "stac/log.hpp"
#include "stac/robot_model.hpp"
#include "stac/sensors.hpp"

namespace stac {

struct CalibrationOptions;

// Seed uncertainties (one standard deviation) and process noise. The θ
// entries are the ones in MeasurementModel's layout; each std below is
// multiplied by theta_std_scale.
struct EkfOptions {
  // q_0 (one value per joint of q); empty: solved from frame 0 at the seed.
  Eigen::VectorXd initial_q;
  double initial_q_std = 0.05;          // rad (m) when initial_q is given
  double solved_q_std_fraction = 0.25;  // of each joint's range otherwise
  // Σ_q per frame = (q_speed * range_j * dt)²: a random walk whose typical
  // speed is q_speed joint ranges per second. Large (the paper: "a drift
  // term with large variance"), so that each q_t follows its own frame's
  // readings: real motion reaches a few ranges per second, and a random walk
  // narrower than the motion makes the filter blame θ for it.
  double q_speed = 10.0;
  double rate_hz = 0.0;  // frames per second; 0: from the log's time column, else 100
  // Measurement updates per frame: 1 is the paper's EKF; more is the
  // iterated EKF (relinearised at the updated state, Gauss-Newton on the
  // frame's posterior), which follows fast motion much better.
  int iterations = 1;
  double theta_std_scale = 1.0;
  double rotation_std = 0.2;       // rad, mocap rotation (each axis)
  double translation_std = 0.1;    // m, mocap translation
  double marker_std = 0.05;        // m, marker position (each axis)
  double gain_std = 0.3;           // relative to max(|seed gain|, 1)
  double joint_bias_std = 0.3;     // rad, times max(|seed gain|, 1)
  double tendon_bias_std = 0.02;   // m, times max(|seed gain|, 1)

  bool isValid(std::string* error) const;
};

// Runs the filter (calibrate() dispatches here for Method::kEkf). Uses
// options.ekf, threads (for the statistics afterwards), loss, progress (one
// report per ~10% of the frames: innovation cost and RMS of that stretch).
// The seed σ are used throughout (no variance adaptation). joint_angles
// receives the filtered q_t. std comes from the final covariance; parameters
// the data cannot determine (estimateUncertainty at the final θ and the
// filtered q_t) are listed and get an infinite std.
CalibrationResult calibrateEkf(const RobotModel& robot, const SensorSet& sensors,
                               const SensorParameters& seed, const Observations& obs,
                               const CalibrationOptions& options,
                               RowMatrix* joint_angles = nullptr);

// The first row of a joint-angles log (as written by --joint-angles) as q:
// the log's columns must be exactly the joints of q, in any order. Throws
// InputError naming the log and line for an unknown or missing joint, an
// empty log or a missing value.
Eigen::VectorXd firstJointAngles(const Log& log, const RobotModel& robot);

}  // namespace stac
