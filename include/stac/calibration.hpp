// What a calibration run produces besides θ: uncertainties, residual
// statistics and a summary (SPEC §3 "std", "residual", "summary").
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "stac/sensors.hpp"

namespace stac {

struct ResidualStats {
  double rms = 0.0;   // raw units (metres for markers: Euclidean distance)
  double mae = 0.0;
  int count = 0;
};

// One standard deviation per estimated parameter, +inf where the data cannot
// determine it, 0 where the parameter is fixed.
struct ParameterStd {
  Eigen::Vector3d mocap_translation = Eigen::Vector3d::Zero();
  Eigen::Vector3d mocap_rotation = Eigen::Vector3d::Zero();  // rad, about x,y,z
  std::vector<Eigen::Vector3d> marker_position;
  std::vector<GainBias> joint_sensor;   // std of gain and of bias
  std::vector<GainBias> tendon_sensor;
  std::vector<OriginCorrection> joint_origin;  // std of each component
};

// Why the data leave a direction open: what a fit that sits anywhere along
// it says about where the joints' motions lie.
enum class Undetermined {
  kNull,         // exactly null: a gauge, any value fits alike
  kWeak,         // determined, but too weakly for a std (the data still prefer a value)
  kModuloTurn,   // a bias known only modulo a whole turn
  kStillJoint,   // the log does not move the joint (its angle comes from other readings)
  kMirror,       // a discrete alternative (a mirror configuration) fits as well
};

// The kind's name in the calibration YAML (summary.unidentifiable[].kind),
// the Python dicts and the report: what a script tells the kinds apart by.
inline const char* undeterminedName(Undetermined kind) {
  switch (kind) {
    case Undetermined::kNull: return "null_direction";
    case Undetermined::kWeak: return "weak";
    case Undetermined::kModuloTurn: return "modulo_turn";
    case Undetermined::kStillJoint: return "still_joint";
    case Undetermined::kMirror: return "mirror";
  }
  return "weak";
}

struct UnidentifiableDirection {
  std::vector<std::string> parameters;  // e.g. "joint_sensors.pan_pot.bias"
  std::string reason;                   // one human sentence
  Undetermined kind = Undetermined::kWeak;
};

// With a prior on the joint-origin corrections: which components of one
// joint's correction the data determines (posterior std below half the
// prior's) and which stay on the prior (component names x, y, z, roll,
// pitch, yaw).
struct OriginDetermination {
  std::string joint;
  std::vector<std::string> determined, on_prior;
};

struct DownweightedReading {
  int frame = 0;
  std::string sensor;
  double weight = 1.0;  // robust loss weight rho'(s) in [0, 1]
};

struct CalibrationSummary {
  std::string method;        // stac | joint | ekf | classical
  std::string q_phase;       // for stac
  int iterations = 0;
  bool converged = false;
  double initial_cost = 0.0;
  double final_cost = 0.0;
  int frames = 0;
  double wall_time = 0.0;    // seconds
  double group_sigma[kNumSensorGroups] = {0, 0, 0};
  double seed_group_sigma[kNumSensorGroups] = {0, 0, 0};  // the same at the seed σ
  bool group_present[kNumSensorGroups] = {false, false, false};
  // RMS residual per group in raw units: with the seed θ (each q_t fitted
  // to it) and after calibration.
  double before_rms[kNumSensorGroups] = {0, 0, 0};
  double after_rms[kNumSensorGroups] = {0, 0, 0};
  std::vector<UnidentifiableDirection> unidentifiable;
  std::vector<OriginDetermination> origins;  // one per corrected joint with free parts
  std::vector<DownweightedReading> downweighted;
  // Readings set aside before the fit as spikes in time (robust loss only:
  // solve/spike_screen.hpp), per group.
  int spikes_set_aside[kNumSensorGroups] = {0, 0, 0};
  // The result's own checks (SPEC §3 summary.verdict): empty when it passed
  // them ("ok"), else one sentence per failed check. stac_calib exits 4 on a
  // non-empty verdict.
  std::vector<std::string> verdict;
  bool suspect() const { return !verdict.empty(); }
};

struct CalibrationResult {
  SensorSet sensors;             // with final σ per sensor
  SensorParameters theta;
  ParameterStd std;
  std::vector<ResidualStats> marker_residual, joint_residual, tendon_residual;
  CalibrationSummary summary;
};

}  // namespace stac
