// Cross-sensor prediction on held-out data (SPEC §4 stac_eval; paper
// Tables I, II): with θ fixed, estimate q_t of every frame from some sensor
// groups only, then predict every group from q_t and report the mean
// absolute error of the predictions against the readings.
//
//   EvaluationOptions options;
//   options.use[static_cast<int>(SensorGroup::kJoint)] = true;
//   EvaluationResult r = evaluatePrediction(robot, sensors, theta, obs, options);
//   // r.group[g].mae, r.sensors[i].mae ...
//
// MAE of a marker: mean Euclidean distance (metres) between the predicted and
// the measured position, over the frames where it is present; of a joint or
// tendon sensor: mean |prediction - reading| in its raw unit. A group's MAE
// pools every reading of its sensors. The library never prints: report and
// JSON text are returned as strings.
#pragma once

#include <string>
#include <vector>

#include "stac/log.hpp"
#include "stac/robot_model.hpp"
#include "stac/sensors.hpp"

namespace stac {

struct EvaluationOptions {
  // Groups whose readings estimate q (the others get weight 0).
  bool use[kNumSensorGroups] = {false, false, false};
  // Groups to predict; a group without sensors is skipped.
  bool predict[kNumSensorGroups] = {true, true, true};
  int threads = 0;           // 0: all cores
  int tracking_segments = 8; // runs of frames tracked from the neutral pose
  int refinements = 2;       // lm-batch passes after the tracking pass
  int max_steps = 50;        // LM steps per frame and pass

  // At least one group used, threads >= 0, segments >= 1, refinements >= 0,
  // max_steps >= 1. On failure *error (if given) says which and why.
  bool isValid(std::string* error) const;
};

struct SensorPredictionError {
  std::string name;
  SensorGroup group = SensorGroup::kJoint;
  int index = 0;        // within its group
  double mae = 0.0;     // NaN when count == 0
  int count = 0;        // readings compared
};

struct GroupPredictionError {
  bool present = false;    // the sensors file has sensors of this group
  bool predicted = false;  // present and asked for
  bool used = false;       // its readings estimated q (paper: in parentheses)
  double mae = 0.0;        // NaN when count == 0 or not predicted
  int count = 0;
};

struct EvaluationResult {
  int frames = 0;
  GroupPredictionError group[kNumSensorGroups];
  std::vector<SensorPredictionError> sensors;  // predicted groups only, in
                                               // marker, joint, tendon order
  RowMatrix q;                                 // frames x dof, the estimate
  // q is bounded by the joint limits widened by 5% of the range (as in
  // calibration): a joint estimated at that bound was clamped, its
  // readings asking for an angle the URDF rules out, and the predictions
  // of that frame carry the difference. Per joint of q, the frames at a
  // bound; and the frames with some joint at one.
  std::vector<int> frames_at_limit;
  std::vector<std::string> q_names;  // the joints of q, for reports
  int frames_clamped = 0;
};

// Throws std::invalid_argument if the options are invalid, a used group has
// no sensors, or obs does not match the sensors.
EvaluationResult evaluatePrediction(const RobotModel& robot, const SensorSet& sensors,
                                    const SensorParameters& theta, const Observations& obs,
                                    const EvaluationOptions& options);

// One row of the paper's Tables I/II: q estimated from the groups of `use`,
// every present group predicted.
struct CrossSensorRow {
  std::string label;   // e.g. "joint+tendon"
  EvaluationResult result;
};

// The rows for every non-empty combination of the groups the sensors have
// (single groups first, then pairs, then all), each evaluated on obs with
// options' solver settings (options.use and options.predict are ignored).
std::vector<CrossSensorRow> crossSensorTable(const RobotModel& robot, const SensorSet& sensors,
                                             const SensorParameters& theta,
                                             const Observations& obs,
                                             const EvaluationOptions& options);

// The rows as a text table, MAE per predicted group. Parenthesised values:
// the group also estimated q (the model's fit rather than a prediction).
std::string crossSensorTableText(const std::vector<CrossSensorRow>& rows);

// One parameter's error against a known truth.
struct ParameterError {
  std::string name;  // "<sensor>.gain", "<sensor>.bias", "<marker>.position",
                     // "mocap.translation", "mocap.rotation"
  double error = 0.0;  // gain, bias: estimate - truth (raw units); position,
                       // translation: |estimate - truth| (m); rotation: angle
                       // of R_estimate R_truthᵀ (rad)
  std::string unit;    // "", "m" or "rad"
};

// Errors of every parameter of (sensors, theta) against (truth_sensors,
// truth), sensors matched by name. Throws InputError(truth_source, ...) if
// the truth lacks a sensor or marker, has one the estimate lacks, or
// attaches one to a different joint or link.
std::vector<ParameterError> compareToTruth(const SensorSet& sensors,
                                           const SensorParameters& theta,
                                           const SensorSet& truth_sensors,
                                           const SensorParameters& truth,
                                           const std::string& truth_source);

// Human-readable report: the table row (used groups in parentheses), the
// per-sensor errors and, if truth != nullptr, the parameter errors.
std::string evaluationReport(const EvaluationResult& result,
                             const std::vector<ParameterError>* truth = nullptr);

// {"frames": N, "use": [...], "mae": {...}, "per_sensor": {"<name>": {"mae":
// ..., "count": ...}}} plus "truth": {"<parameter>": error} when truth !=
// nullptr. Undefined numbers are written as null.
std::string evaluationJson(const EvaluationResult& result,
                           const std::vector<ParameterError>* truth = nullptr);

}  // namespace stac
