// Calibration (SPEC §4 stac_calib): the STAC alternation (paper §II-C), one
// monolithic problem, and the paper's two baselines: an EKF (§IV-A) and the
// classical regression with σ_p -> 0 (§IV-B).
//
//   CalibrationOptions options;            // validated by isValid()
//   CalibrationResult r = calibrate(robot, sensors, seed, observations,
//                                   options, &joint_angles);
//   std::cout << r.briefReport();
//
// The library never prints: progress goes to options.progress, a callback.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <string>

#include "stac/calibration.hpp"
#include "stac/log.hpp"
#include "stac/robot_model.hpp"
#include "stac/sensors.hpp"
#include "stac/solver_options.hpp"

namespace stac {

enum class Method {
  kStac,       // alternation of q-phase and θ-phase (default)
  kMonolithic, // one monolithic problem over every q_t and θ (Ceres)
  kEkf,        // extended Kalman filter over [θ; q], one forward pass
  kClassical,  // regression with every joint angle read off its sensor
};

struct IterationReport {
  int iteration = 0;
  double cost = 0.0;                         // ½ Σ ρ at the current σ
  double rms[kNumSensorGroups] = {0, 0, 0};  // raw units (metres, volts...)
  bool present[kNumSensorGroups] = {false, false, false};
  double elapsed = 0.0;                      // seconds since the start
  // The current θ (STAC and joint stages), valid during the callback only:
  // lets experiments trace the parameter error per iteration.
  const SensorParameters* theta = nullptr;
  std::string stage;  // "init", "seed", "stac", "joint", "ekf" (per ~10% of frames), "classical"
};

// Method::kStac and kMonolithic: how the run starts and (kStac) alternates.
struct StacOptions {
  QPhaseMethod q_phase = QPhaseMethod::kLmIter;
  bool wide_basin_init = true;  // marker-led initialisation from a poor seed
  bool coupled_steps = true;    // finish with coupled (q, θ) steps
};

// Method::kEkf (paper §IV-A): state [free θ; q], θ constant, q a random
// walk; every reading through the same sensor models as STAC, whitened by
// the seed σ. The paper (§VI-B) starts q_0 at the truth of the first frame;
// without a given q_0 frame 0 is solved for q at the seed θ.
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

struct CalibrationOptions {
  Method method = Method::kStac;
  // Every method.
  int max_iterations = 200;    // outer iterations (kMonolithic, kClassical: per solve)
  double tolerance = 1e-7;     // stop when the relative cost decrease is below
  int threads = 0;             // 0: all cores
  LossKind loss = LossKind::kNone;
  double loss_scale = 3.0;     // in units of σ
  bool adapt_variance = true;  // one σ per sensor group re-estimated (not kEkf)
  // With a robust loss: readings that stand out of their neighbours in time
  // are set aside before the fit (summary.spikes_set_aside).
  bool screen_spikes = true;
  int max_downweighted = 20;   // readings listed in the summary
  std::function<void(const IterationReport&)> progress;
  // Cancellation (e.g. a front end's Ctrl-C flag): polled before every
  // progress report and after every iteration of each Ceres solve (so a long
  // --method joint solve stops within one iteration). When it returns true
  // calibrate() throws stac::Cancelled and returns nothing. It is called
  // from the calibrating thread only; it must be cheap and must not throw.
  // An exception thrown by `progress` itself propagates out of calibrate()
  // the same way.
  std::function<bool()> should_stop;
  // One method's own.
  StacOptions stac;            // kStac, kMonolithic
  EkfOptions ekf;              // kEkf

  bool isValid(std::string* error) const;
};

// q0: initial joint angles (frames x dof), or nullptr for the wide-basin
// start from the seed (the EKF uses q0's first row unless options.ekf.initial_q
// is set; the classical regression ignores it). joint_angles (optional)
// receives the final q_t (kClassical: read off the sensors, NaN where a
// defining reading is missing; kEkf: the filtered q_t). Throws
// std::invalid_argument for invalid options or data the method cannot use
// (kClassical: a joint without a one-joint sensor); stac::Cancelled when
// options.should_stop asked to stop.
CalibrationResult calibrate(const RobotModel& robot, const SensorSet& sensors,
                            const SensorParameters& seed, const Observations& obs,
                            const CalibrationOptions& options,
                            RowMatrix* joint_angles = nullptr,
                            const RowMatrix* q0 = nullptr);

// calibrate() from the wide-basin start as the front ends run it (stac_calib,
// the Python module), on sensors read from `sensors_source`: a sensors file,
// or the log they were inferred from. Sensors the method cannot calibrate
// (std::invalid_argument, e.g. kClassical and a joint without a one-joint
// sensor) are bad input in that file: an InputError naming it. Options are
// the caller's to validate first (isValid), or they are reported so too.
CalibrationResult calibrateFromSource(const std::string& sensors_source, const RobotModel& robot,
                                      const SensorSet& sensors, const SensorParameters& seed,
                                      const Observations& obs, const CalibrationOptions& options,
                                      RowMatrix* joint_angles);

// A human summary of r (what stac_calib prints): the run, residual RMS per
// group before and after, the parameters that moved most from `seed`, the
// unidentifiable directions and the down-weighted readings.
std::string briefReport(const RobotModel& robot, const SensorParameters& seed,
                        const CalibrationResult& r);

// The neutral pose: 0 clamped into each joint's limits (where q starts).
Eigen::VectorXd neutralPose(const RobotModel& robot);

}  // namespace stac
