// The likelihood of one frame (paper eq. 9, SPEC §1): every available
// reading's residual (prediction - measurement) / σ, optionally robustified,
// with its Jacobians with respect to q_t and to θ.
//
// MeasurementModel is built once from a RobotModel and a SensorSet (both must
// outlive it): it resolves which q columns each sensor depends on; θ's
// layout (the columns of dr/dθ) is its ThetaSpace's (theta_space.hpp).
// FrameWorkspace holds every per-thread buffer; evaluation never allocates.
#pragma once

#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "stac/kinematics.hpp"
#include "stac/log.hpp"
#include "stac/robot_model.hpp"
#include "stac/sensors.hpp"
#include "stac/solver_options.hpp"
#include "stac/theta_space.hpp"

namespace ceres {
class LossFunction;
}

namespace stac {

// Effective σ of every sensor (seed σ times the group's adapted scale).
struct NoiseModel {
  std::vector<double> marker, joint, tendon;
  static NoiseModel fromSeeds(const SensorSet& sensors);
  double sigma(SensorGroup group, int sensor) const {
    return group == SensorGroup::kMarker  ? marker[sensor]
           : group == SensorGroup::kJoint ? joint[sensor]
                                          : tendon[sensor];
  }
};

// A robust loss ρ(s) on the squared whitened residual s of one reading
// (Ceres's convention: ρ(s) = s for small s). Owns a Ceres loss so that the
// alternation and the monolithic problem use the very same function.
class RobustLoss {
 public:
  RobustLoss(LossKind kind = LossKind::kNone, double scale = 3.0);
  ~RobustLoss();
  RobustLoss(RobustLoss&&) noexcept;
  RobustLoss& operator=(RobustLoss&&) noexcept;
  bool enabled() const { return kind_ != LossKind::kNone; }
  LossKind kind() const { return kind_; }
  double scale() const { return scale_; }
  // rho[0] = ρ(s), rho[1] = ρ'(s), rho[2] = ρ''(s).
  void evaluate(double s, double rho[3]) const;
  // A new Ceres loss of the same kind (nullptr for none); caller owns it.
  ceres::LossFunction* makeCeresLoss() const;

 private:
  LossKind kind_;
  double scale_;
  std::unique_ptr<ceres::LossFunction> loss_;
};

class MeasurementModel {
 public:
  MeasurementModel(const RobotModel& robot, const SensorSet& sensors);

  const RobotModel& robot() const { return *robot_; }
  const SensorSet& sensors() const { return *sensors_; }
  int dof() const { return robot_->dof(); }
  int numReadingsMax() const { return num_sensors_; }

  const std::vector<int>& markerColumns(int m) const { return marker_cols_[m]; }
  // For each of the marker's link's supporting joints (RobotModel order),
  // its position in markerColumns(m).
  const std::vector<int>& markerSlots(int m) const { return marker_slots_[m]; }
  const std::vector<int>& jointColumns(int s) const { return joint_cols_[s]; }
  const std::vector<int>& tendonColumns(int s) const { return tendon_cols_[s]; }
  // The joint-origin corrections (SensorSet::joint_origins indices) that
  // move marker m, or any anchor of tendon path s; and, per anchor k of
  // path s, the positions among tendonOrigins(s) of those that move it.
  const std::vector<int>& markerOrigins(int m) const { return marker_origins_[m]; }
  const std::vector<int>& tendonOrigins(int s) const { return tendon_origins_[s]; }
  const std::vector<std::vector<int>>& anchorOriginSlots(int s) const { return anchor_slots_[s]; }
  // The widest θ-Jacobian of one reading (columns).
  int thetaWidthMax() const { return theta_width_; }

  // θ's layout: the columns of every dr/dθ.
  const ThetaSpace& thetaSpace() const { return theta_space_; }

 private:
  void resolveOrigins();

  const RobotModel* robot_;
  const SensorSet* sensors_;
  int num_sensors_ = 0;
  std::vector<std::vector<int>> marker_cols_, joint_cols_, tendon_cols_;
  std::vector<std::vector<int>> marker_slots_;
  std::vector<std::vector<int>> marker_origins_, tendon_origins_;
  std::vector<std::vector<std::vector<int>>> anchor_slots_;
  int theta_width_ = 9;
  ThetaSpace theta_space_;
};

// One reading's whitened (and robustified) residual and Jacobians.
struct ReadingJacobian {
  SensorGroup group = SensorGroup::kJoint;
  int sensor = 0;         // index within its group
  int rows = 1;           // 1, or 3 for a marker
  Eigen::Vector3d r = Eigen::Vector3d::Zero();
  double s = 0.0;         // squared whitened residual before the loss
  double rho = 0.0;       // ρ(s)
  double weight = 1.0;    // ρ'(s): how much the loss trusts this reading
  const std::vector<int>* q_cols = nullptr;
  Eigen::Matrix<double, 3, Eigen::Dynamic> Jq;  // rows x q_cols->size()
  int theta_count = 0;
  std::vector<int> theta_index;                  // MeasurementModel::thetaWidthMax()
  Eigen::Matrix<double, 3, Eigen::Dynamic> Jtheta;  // 3 x thetaWidthMax()
};

// The readings of one frame, as pointers into the Observations rows.
struct FrameReadings {
  const double* marker = nullptr;  // 3 * markers, NaN missing
  const double* joint = nullptr;
  const double* tendon = nullptr;
};
FrameReadings frameReadings(const Observations& obs, int t);

struct FrameWorkspace {
  explicit FrameWorkspace(const MeasurementModel& model);
  KinematicsWorkspace kin;
  std::vector<ReadingJacobian> readings;
  int count = 0;                  // readings filled by the last evaluation
  Eigen::RowVectorXd row;         // dof scratch
};

// Evaluates frame t at q. Returns the frame's cost ½ Σ ρ(s). With
// jacobians=false only r, s, rho, weight are filled. Group weights multiply
// each group's whitened residuals (0 switches a group off).
struct FrameOptions {
  bool jacobians = true;
  bool theta_jacobians = false;
  double group_weight[kNumSensorGroups] = {1.0, 1.0, 1.0};
};
double evaluateFrame(const MeasurementModel& model, const SensorParameters& theta,
                     const NoiseModel& noise, const RobustLoss& loss,
                     const FrameReadings& readings, const Eigen::VectorXd& q,
                     const FrameOptions& options, FrameWorkspace* ws);

}  // namespace stac

namespace stac {

// Points the kinematics in ws at θ's joint-origin corrections (a no-op
// without any): every evaluation below does it itself; code that runs
// forwardKinematics() on its own calls it first.
void applyJointOrigins(const MeasurementModel& model, const SensorParameters& theta,
                       KinematicsWorkspace* ws);

// Noise-free predicted readings of every sensor at q, in raw units (mocap
// frame for markers): marker (3 * markers), joint, tendon.
void predictFrame(const MeasurementModel& model, const SensorParameters& theta,
                  const Eigen::VectorXd& q, KinematicsWorkspace* ws,
                  double* marker, double* joint, double* tendon);

}  // namespace stac
