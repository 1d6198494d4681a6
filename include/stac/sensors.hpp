// The sensors of a robot (SPEC §1, §3): configuration apart from the values
// being estimated.
//
// SensorSet is the immutable description: names, the links/joints each sensor
// is attached to (resolved to indices once, against a RobotModel), path
// anchors and coupling coefficients (known geometry), which parameters are
// held fixed, and the noise σ seeds. SensorParameters (θ) holds the values
// that calibration estimates: gains/biases, marker positions, the mocap frame.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "stac/joint_origins.hpp"

namespace stac {

// x_mocap = R x_base + t: the pose of the robot base in the mocap frame.
struct MocapFrame {
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
};

// Which of a linear sensor's parameters are held at their given values
// (SPEC §3: `fixed: true`, `false`, `[gain]` or `[bias]`).
struct FixedGainBias {
  bool gain = false;
  bool bias = false;
  static FixedGainBias both(bool held) { return {held, held}; }
  bool all() const { return gain && bias; }
  bool any() const { return gain || bias; }
  bool operator==(const FixedGainBias& o) const { return gain == o.gain && bias == o.bias; }
};

// Which parts of the mocap frame are held (`[rotation]`, `[translation]`).
struct FixedFrame {
  bool rotation = false;
  bool translation = false;
  static FixedFrame both(bool held) { return {held, held}; }
  bool all() const { return rotation && translation; }
  bool any() const { return rotation || translation; }
  bool operator==(const FixedFrame& o) const {
    return rotation == o.rotation && translation == o.translation;
  }
};

struct MarkerConfig {
  std::string name;
  std::string link_name;
  int link = -1;             // RobotModel link index
  double sigma = 0.002;      // metres (mocap.sigma unless overridden)
  bool sigma_overridden = false;
  bool fixed = false;
  // The log columns of x, y, z when they are not <name>.x/.y/.z (SPEC §3
  // `columns:`); empty strings for the default.
  std::array<std::string, 3> columns;
  std::array<std::string, 3> logColumns() const;
};

struct JointSensorConfig {
  std::string name;
  std::string joint_name;
  int joint = -1;            // RobotModel movable joint index (may be mimic)
  double sigma = 0.01;
  FixedGainBias fixed;
  std::string column;  // the log column when not `name` (SPEC §3 `column:`)
  const std::string& logColumn() const { return column.empty() ? name : column; }
};

struct PathAnchor {
  std::string link_name;
  int link = -1;
  Eigen::Vector3d point = Eigen::Vector3d::Zero();  // in the link's frame
};

struct CouplingTerm {
  std::string joint_name;
  int joint = -1;            // movable joint index (may be mimic)
  double coefficient = 0.0;
};

struct TendonSensorConfig {
  enum class Kind { kPath, kCoupling };
  std::string name;
  Kind kind = Kind::kPath;
  std::vector<PathAnchor> path;        // kPath: >= 2 anchors
  std::vector<CouplingTerm> coupling;  // kCoupling
  double sigma = 0.01;
  FixedGainBias fixed;
  std::string column;  // the log column when not `name` (SPEC §3 `column:`)
  const std::string& logColumn() const { return column.empty() ? name : column; }
};

// Sensor groups, for per-group σ adaptation and reporting (SPEC §1).
enum class SensorGroup { kMarker = 0, kJoint = 1, kTendon = 2 };
constexpr int kNumSensorGroups = 3;
// Residual rows of one reading of each group (a marker's x, y, z).
constexpr int kReadingRows[kNumSensorGroups] = {3, 1, 1};

struct SensorSet {
  double mocap_sigma = 0.002;
  FixedFrame mocap_frame_fixed;
  std::vector<MarkerConfig> markers;
  std::vector<JointSensorConfig> joint_sensors;
  std::vector<TendonSensorConfig> tendon_sensors;
  // Kinematic calibration (optional): the joints whose <origin> is corrected.
  std::vector<JointOriginConfig> joint_origins;
  OriginPrior origin_prior;
  // Log columns that belong to no sensor (SPEC §3 `ignore_columns:`).
  std::vector<std::string> ignore_columns;

  bool hasMarkers() const { return !markers.empty(); }
  // The number of sensors (markers) of group g, and the name of the i-th.
  int groupSize(SensorGroup g) const;
  const std::string& sensorName(SensorGroup g, int i) const;
};

// A linear sensor's map p = gain * value + bias.
struct GainBias {
  double gain = 1.0;
  double bias = 0.0;
};

// θ: everything calibration estimates, indexed like the SensorSet.
struct SensorParameters {
  MocapFrame mocap;
  std::vector<Eigen::Vector3d> marker_position;  // in the marker's link frame
  std::vector<GainBias> joint_sensor;
  std::vector<GainBias> tendon_sensor;
  std::vector<OriginCorrection> joint_origin;  // indexed like SensorSet::joint_origins
};

const char* groupName(SensorGroup g);
// The group groupName gives `name` ("marker", "joint", "tendon"), or none.
std::optional<SensorGroup> groupFromName(const std::string& name);
// The unit of a group's residuals in reports: "m" (markers, Euclidean), "raw"
// (a sensor's own unit).
const char* groupUnit(SensorGroup g);

}  // namespace stac
