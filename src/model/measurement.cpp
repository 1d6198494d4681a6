#include "stac/measurement.hpp"

#include <ceres/loss_function.h>

#include <algorithm>
#include <cmath>

#include "stac/sensor_models.hpp"

namespace stac {

NoiseModel NoiseModel::fromSeeds(const SensorSet& sensors) {
  NoiseModel n;
  for (const MarkerConfig& m : sensors.markers) n.marker.push_back(m.sigma);
  for (const JointSensorConfig& s : sensors.joint_sensors) n.joint.push_back(s.sigma);
  for (const TendonSensorConfig& s : sensors.tendon_sensors) n.tendon.push_back(s.sigma);
  return n;
}

RobustLoss::RobustLoss(LossKind kind, double scale) : kind_(kind), scale_(scale) {
  if (kind == LossKind::kHuber) loss_ = std::make_unique<ceres::HuberLoss>(scale);
  if (kind == LossKind::kCauchy) loss_ = std::make_unique<ceres::CauchyLoss>(scale);
}
RobustLoss::~RobustLoss() = default;
RobustLoss::RobustLoss(RobustLoss&&) noexcept = default;
RobustLoss& RobustLoss::operator=(RobustLoss&&) noexcept = default;

void RobustLoss::evaluate(double s, double rho[3]) const {
  if (!loss_) {
    rho[0] = s, rho[1] = 1.0, rho[2] = 0.0;
    return;
  }
  loss_->Evaluate(s, rho);
}

ceres::LossFunction* RobustLoss::makeCeresLoss() const {
  switch (kind_) {
    case LossKind::kHuber: return new ceres::HuberLoss(scale_);
    case LossKind::kCauchy: return new ceres::CauchyLoss(scale_);
    case LossKind::kNone: break;
  }
  return nullptr;
}

MeasurementModel::MeasurementModel(const RobotModel& robot, const SensorSet& sensors)
    : robot_(&robot), sensors_(&sensors), theta_space_(sensors) {
  for (const MarkerConfig& m : sensors.markers) {
    marker_cols_.push_back(marker_sensor::columns(robot, m.link));
    const std::vector<int>& cols = marker_cols_.back();
    std::vector<int> slots;
    for (int j : robot.supportingJoints(m.link))
      slots.push_back(static_cast<int>(
          std::find(cols.begin(), cols.end(), robot.movableJoints()[j].q_index) - cols.begin()));
    marker_slots_.push_back(std::move(slots));
  }
  for (const JointSensorConfig& s : sensors.joint_sensors)
    joint_cols_.push_back({joint_sensor::column(robot, s)});
  for (const TendonSensorConfig& s : sensors.tendon_sensors)
    tendon_cols_.push_back(tendon_sensor::columns(robot, s));
  resolveOrigins();
  num_sensors_ = static_cast<int>(sensors.markers.size() + sensors.joint_sensors.size() +
                                  sensors.tendon_sensors.size());
}

void MeasurementModel::resolveOrigins() {
  const std::vector<int>& links = theta_space_.originLinks();
  for (const MarkerConfig& m : sensors_->markers) {
    marker_origins_.push_back(supportingCorrections(*robot_, links, m.link));
    theta_width_ = std::max(theta_width_, 9 + 6 * static_cast<int>(marker_origins_.back().size()));
  }
  for (const TendonSensorConfig& s : sensors_->tendon_sensors) {
    std::vector<int> all;
    std::vector<std::vector<int>> per_anchor;
    for (const PathAnchor& a : s.path) {
      per_anchor.push_back(supportingCorrections(*robot_, links, a.link));
      for (int c : per_anchor.back())
        if (std::find(all.begin(), all.end(), c) == all.end()) all.push_back(c);
    }
    for (std::vector<int>& anchor : per_anchor)
      for (int& c : anchor) c = static_cast<int>(std::find(all.begin(), all.end(), c) - all.begin());
    theta_width_ = std::max(theta_width_, 2 + 6 * static_cast<int>(all.size()));
    tendon_origins_.push_back(std::move(all));
    anchor_slots_.push_back(std::move(per_anchor));
  }
}

void applyJointOrigins(const MeasurementModel& model, const SensorParameters& theta,
                       KinematicsWorkspace* ws) {
  if (model.sensors().joint_origins.empty() && ws->applied.empty()) return;
  setOriginCorrections(model.robot(), model.thetaSpace().originLinks(), theta.joint_origin, ws);
}

FrameReadings frameReadings(const Observations& obs, int t) {
  FrameReadings f;
  if (obs.marker.cols() > 0) f.marker = obs.marker.row(t).data();
  if (obs.joint.cols() > 0) f.joint = obs.joint.row(t).data();
  if (obs.tendon.cols() > 0) f.tendon = obs.tendon.row(t).data();
  return f;
}

FrameWorkspace::FrameWorkspace(const MeasurementModel& model)
    : kin(model.robot()),
      readings(model.numReadingsMax()),
      row(model.dof()) {
  // Readings fill the slots in order, skipping missing ones, so any slot may
  // hold any sensor: size each for the widest.
  size_t widest = 1;
  const SensorSet& s = model.sensors();
  for (size_t m = 0; m < s.markers.size(); ++m)
    widest = std::max(widest, model.markerColumns(static_cast<int>(m)).size());
  for (size_t j = 0; j < s.tendon_sensors.size(); ++j)
    widest = std::max(widest, model.tendonColumns(static_cast<int>(j)).size());
  for (ReadingJacobian& r : readings) {
    r.Jq.resize(3, static_cast<Eigen::Index>(widest));
    r.theta_index.assign(model.thetaWidthMax(), 0);
    r.Jtheta.setZero(3, model.thetaWidthMax());
  }
}

namespace {

// Replaces the whitened residual r (n rows) by sqrt(ρ(s)/s) r, whose squared
// norm is ρ(s), and its Jacobians by the exact derivative of that map, so a
// plain least-squares solver minimises Σ ρ. Returns ρ(s).
void robustify(const RobustLoss& loss, ReadingJacobian* rj, bool jac, int nq) {
  const int n = rj->rows;
  const double s = rj->r.head(n).squaredNorm();
  double rho[3];
  loss.evaluate(s, rho);
  rj->s = s;
  rj->rho = rho[0];
  rj->weight = rho[1];
  if (!loss.enabled()) return;
  if (s < 1e-300) return;  // ρ(s) ≈ s near zero: the map is the identity
  // f = sqrt(ρ/s) and d f / d s = (ρ' s - ρ) / (2 s² f). Near s = 0 both
  // lose everything to rounding (a Cauchy loss evaluates ρ = log(1 + s/c²)
  // as 0 for s ~ 1e-16: f = 0, df = -inf, and NaN std for every parameter);
  // there their expansions about s: ρ/s = ρ' - ρ'' s / 2 and df = ρ'' / (4 f),
  // to a relative 1e-6.
  const bool near_zero = s < 1e-6;
  const double f = std::sqrt(near_zero ? rho[1] - 0.5 * rho[2] * s : rho[0] / s);
  const double df = near_zero ? rho[2] / (4.0 * f) : (rho[1] * s - rho[0]) / (2.0 * s * s * f);
  if (jac) {
    // J' = f J + r (df * 2 r^T J)
    const Eigen::VectorXd r = rj->r.head(n);
    if (nq > 0) {
      Eigen::RowVectorXd rtJ = r.transpose() * rj->Jq.topLeftCorner(n, nq);
      rj->Jq.topLeftCorner(n, nq) = f * rj->Jq.topLeftCorner(n, nq) + (2.0 * df) * r * rtJ;
    }
    if (rj->theta_count > 0) {
      const int k = rj->theta_count;
      Eigen::RowVectorXd rtJ = r.transpose() * rj->Jtheta.topLeftCorner(n, k);
      rj->Jtheta.topLeftCorner(n, k) =
          f * rj->Jtheta.topLeftCorner(n, k) + (2.0 * df) * r * rtJ;
    }
  }
  rj->r.head(n) *= f;
}

}  // namespace

namespace {

// Marker m's reading x: r = (R h_k(q) d + t - x) w / σ, its q-Jacobian (the
// point Jacobian straight into this reading's own columns, no 3 x dof
// scratch to zero and gather, then rotated and whitened) and θ-Jacobian.
void markerReading(const MeasurementModel& model, const SensorParameters& theta,
                   const Eigen::Matrix3d& R, int m, const double* x, double inv,
                   const FrameOptions& options, FrameWorkspace* ws, ReadingJacobian* rj) {
  const MarkerConfig& mc = model.sensors().markers[m];
  rj->group = SensorGroup::kMarker;
  rj->sensor = m;
  rj->rows = 3;
  const Eigen::Vector3d xb =
      marker_sensor::positionInBase(ws->kin, mc.link, theta.marker_position[m]);
  rj->r = (marker_sensor::predict(R, theta.mocap.translation, xb) -
           Eigen::Vector3d(x[0], x[1], x[2])) * inv;
  const std::vector<int>& cols = model.markerColumns(m);
  rj->q_cols = &cols;
  if (options.jacobians) {
    rj->Jq.leftCols(cols.size()).setZero();
    addPointJacobian(model.robot(), ws->kin, mc.link, xb, model.markerSlots(m).data(), rj->Jq);
    const Eigen::Matrix3d M = inv * R;
    for (size_t c = 0; c < cols.size(); ++c) {
      const Eigen::Vector3d v = rj->Jq.col(c);
      rj->Jq.col(c) = M * v;
    }
  }
  rj->theta_count = 0;
  if (!options.theta_jacobians) return;
  const int mo = model.thetaSpace().markerOffset(m);
  rj->theta_count = 9;
  for (int i = 0; i < 3; ++i) {
    rj->theta_index[i] = ThetaSpace::kRotationOffset + i;
    rj->theta_index[3 + i] = ThetaSpace::kTranslationOffset + i;
    rj->theta_index[6 + i] = mo + i;
  }
  rj->Jtheta.block<3, 3>(0, 0) = inv * marker_sensor::rotationJacobian(R, xb);
  rj->Jtheta.block<3, 3>(0, 3) = inv * Eigen::Matrix3d::Identity();
  rj->Jtheta.block<3, 3>(0, 6) = inv * (R * ws->kin.link_pose[mc.link].linear());
  // Joint-origin corrections upstream of the marker: R d(x_b)/d(correction).
  const ThetaSpace& space = model.thetaSpace();
  for (int c : model.markerOrigins(m)) {
    const int col = rj->theta_count;
    for (int i = 0; i < 6; ++i) rj->theta_index[col + i] = space.originOffset(c) + i;
    Eigen::Matrix<double, 3, 6> J = Eigen::Matrix<double, 3, 6>::Zero();
    addOriginJacobian(ws->kin, c, xb, 1.0, J);
    rj->Jtheta.block<3, 6>(0, col) = (inv * R) * J;
    rj->theta_count += 6;
  }
}

// A path tendon's dL/d(correction) for the corrections that move its
// anchors, times `scale`, into rj's θ-Jacobian after its (gain, bias).
void tendonOriginJacobian(const MeasurementModel& model, int s, const KinematicsWorkspace& kin,
                          double scale, ReadingJacobian* rj) {
  const std::vector<int>& origins = model.tendonOrigins(s);
  if (origins.empty()) return;
  const int first = rj->theta_count, width = 6 * static_cast<int>(origins.size());
  for (size_t i = 0; i < origins.size(); ++i)
    for (int k = 0; k < 6; ++k)
      rj->theta_index[first + 6 * i + k] = model.thetaSpace().originOffset(origins[i]) + k;
  rj->Jtheta.block(0, first, 3, width).setZero();
  tendon_sensor::addOriginLengthJacobian(model.sensors().tendon_sensors[s], kin, origins,
                                         model.anchorOriginSlots(s), scale,
                                         rj->Jtheta.row(0).segment(first, width));
  rj->theta_count += width;
}

// A linear sensor's reading p of `value`: r = (g value + b - p) w / σ and
// its θ-Jacobian over (gain, bias) at `offset`.
void gainBiasReading(SensorGroup group, int sensor, const GainBias& gb, double value, double p,
                     double inv, int offset, bool theta_jacobians, ReadingJacobian* rj) {
  rj->group = group;
  rj->sensor = sensor;
  rj->rows = 1;
  rj->r[0] = (gb.gain * value + gb.bias - p) * inv;
  rj->theta_count = 0;
  if (!theta_jacobians) return;
  rj->theta_count = 2;
  rj->theta_index[0] = offset;
  rj->theta_index[1] = offset + 1;
  rj->Jtheta(0, 0) = inv * value;
  rj->Jtheta(0, 1) = inv;
}

// Each group's readings into ws->readings[*k...], their ρ added to *cost.
void markerReadings(const MeasurementModel& model, const SensorParameters& theta,
                      const NoiseModel& noise, const RobustLoss& loss, const double* readings,
                      const FrameOptions& options, FrameWorkspace* ws, int* k, double* cost) {
  const double w = options.group_weight[0];
  if (!readings || !(w > 0)) return;
  const Eigen::Matrix3d R = theta.mocap.rotation.toRotationMatrix();
  for (size_t m = 0; m < model.sensors().markers.size(); ++m) {
    const double* x = readings + 3 * m;
    if (std::isnan(x[0])) continue;
    ReadingJacobian& rj = ws->readings[(*k)++];
    markerReading(model, theta, R, static_cast<int>(m), x, w / noise.marker[m], options, ws, &rj);
    robustify(loss, &rj, options.jacobians, static_cast<int>(rj.q_cols->size()));
    *cost += rj.rho;  // one running sum over the frame's readings
  }
}

void jointReadings(const MeasurementModel& model, const SensorParameters& theta,
                     const NoiseModel& noise, const RobustLoss& loss, const double* readings,
                     const Eigen::VectorXd& q, const FrameOptions& options, FrameWorkspace* ws,
                     int* k, double* cost) {
  const double w = options.group_weight[1];
  if (!readings || !(w > 0)) return;
  const RobotModel& robot = model.robot();
  for (size_t s = 0; s < model.sensors().joint_sensors.size(); ++s) {
    const double p = readings[s];
    if (std::isnan(p)) continue;
    const JointSensorConfig& sc = model.sensors().joint_sensors[s];
    const GainBias& gb = theta.joint_sensor[s];
    ReadingJacobian& rj = ws->readings[(*k)++];
    const int si = static_cast<int>(s);
    const double inv = w / noise.joint[s];
    gainBiasReading(SensorGroup::kJoint, si, gb, joint_sensor::angle(robot, sc, q), p, inv,
                    model.thetaSpace().jointOffset(si), options.theta_jacobians, &rj);
    rj.q_cols = &model.jointColumns(si);
    if (options.jacobians) rj.Jq(0, 0) = inv * gb.gain * joint_sensor::angleDerivative(robot, sc);
    robustify(loss, &rj, options.jacobians, 1);
    *cost += rj.rho;  // one running sum over the frame's readings
  }
}

void tendonReadings(const MeasurementModel& model, const SensorParameters& theta,
                      const NoiseModel& noise, const RobustLoss& loss, const double* readings,
                      const FrameOptions& options, FrameWorkspace* ws, int* k, double* cost) {
  const double w = options.group_weight[2];
  if (!readings || !(w > 0)) return;
  const RobotModel& robot = model.robot();
  for (size_t s = 0; s < model.sensors().tendon_sensors.size(); ++s) {
    const double p = readings[s];
    if (std::isnan(p)) continue;
    const TendonSensorConfig& sc = model.sensors().tendon_sensors[s];
    const GainBias& gb = theta.tendon_sensor[s];
    ReadingJacobian& rj = ws->readings[(*k)++];
    const int si = static_cast<int>(s);
    const double inv = w / noise.tendon[s];
    gainBiasReading(SensorGroup::kTendon, si, gb, tendon_sensor::length(robot, sc, ws->kin), p,
                    inv, model.thetaSpace().tendonOffset(si), options.theta_jacobians, &rj);
    if (options.theta_jacobians) tendonOriginJacobian(model, si, ws->kin, inv * gb.gain, &rj);
    const std::vector<int>& cols = model.tendonColumns(si);
    rj.q_cols = &cols;
    if (options.jacobians) {
      ws->row.setZero();
      tendon_sensor::addLengthJacobian(robot, sc, ws->kin, inv * gb.gain, ws->row);
      for (size_t c = 0; c < cols.size(); ++c) rj.Jq(0, c) = ws->row[cols[c]];
    }
    robustify(loss, &rj, options.jacobians, static_cast<int>(cols.size()));
    *cost += rj.rho;  // one running sum over the frame's readings
  }
}

}  // namespace

double evaluateFrame(const MeasurementModel& model, const SensorParameters& theta,
                     const NoiseModel& noise, const RobustLoss& loss,
                     const FrameReadings& readings, const Eigen::VectorXd& q,
                     const FrameOptions& options, FrameWorkspace* ws) {
  applyJointOrigins(model, theta, &ws->kin);
  forwardKinematics(model.robot(), q, &ws->kin);
  int k = 0;
  double cost = 0.0;
  markerReadings(model, theta, noise, loss, readings.marker, options, ws, &k, &cost);
  jointReadings(model, theta, noise, loss, readings.joint, q, options, ws, &k, &cost);
  tendonReadings(model, theta, noise, loss, readings.tendon, options, ws, &k, &cost);
  ws->count = k;
  return 0.5 * cost;
}

}  // namespace stac

namespace stac {

void predictFrame(const MeasurementModel& model, const SensorParameters& theta,
                  const Eigen::VectorXd& q, KinematicsWorkspace* ws,
                  double* marker, double* joint, double* tendon) {
  const RobotModel& robot = model.robot();
  const SensorSet& sensors = model.sensors();
  applyJointOrigins(model, theta, ws);
  forwardKinematics(robot, q, ws);
  const Eigen::Matrix3d R = theta.mocap.rotation.toRotationMatrix();
  for (size_t m = 0; m < sensors.markers.size(); ++m) {
    const Eigen::Vector3d x = marker_sensor::predict(
        R, theta.mocap.translation,
        marker_sensor::positionInBase(*ws, sensors.markers[m].link, theta.marker_position[m]));
    for (int i = 0; i < 3; ++i) marker[3 * m + i] = x[i];
  }
  for (size_t s = 0; s < sensors.joint_sensors.size(); ++s) {
    const GainBias& gb = theta.joint_sensor[s];
    joint[s] = gb.gain * joint_sensor::angle(robot, sensors.joint_sensors[s], q) + gb.bias;
  }
  for (size_t s = 0; s < sensors.tendon_sensors.size(); ++s) {
    const GainBias& gb = theta.tendon_sensor[s];
    tendon[s] = gb.gain * tendon_sensor::length(robot, sensors.tendon_sensors[s], *ws) + gb.bias;
  }
}

}  // namespace stac
