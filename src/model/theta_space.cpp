#include "stac/theta_space.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace stac {

ThetaSpace::ThetaSpace(const SensorSet& sensors) : sensors_(&sensors) {
  // Without markers nothing sees the mocap frame: it is never free.
  const bool markers = !sensors.markers.empty();
  const FixedFrame& frame = sensors.mocap_frame_fixed;
  auto add = [&](const std::string& name, bool free) {
    names_.push_back(name);
    free_.push_back(free);
  };
  for (const char* axis : {"x", "y", "z"})
    add(std::string("mocap.frame.rotation.") + axis, markers && !frame.rotation);
  for (const char* axis : {"x", "y", "z"})
    add(std::string("mocap.frame.translation.") + axis, markers && !frame.translation);
  for (const MarkerConfig& m : sensors.markers)
    for (const char* axis : {"x", "y", "z"})
      add("markers." + m.name + ".position." + axis, !m.fixed);
  auto gainBias = [&](const std::string& prefix, const FixedGainBias& fixed) {
    add(prefix + ".gain", !fixed.gain);
    add(prefix + ".bias", !fixed.bias);
  };
  joint_offset_ = static_cast<int>(names_.size());
  for (const JointSensorConfig& s : sensors.joint_sensors)
    gainBias("joint_sensors." + s.name, s.fixed);
  tendon_offset_ = static_cast<int>(names_.size());
  for (const TendonSensorConfig& s : sensors.tendon_sensors)
    gainBias("tendon_sensors." + s.name, s.fixed);
  origin_offset_ = static_cast<int>(names_.size());
  for (const JointOriginConfig& o : sensors.joint_origins) {
    origin_links_.push_back(o.link);
    for (const char* axis : {"x", "y", "z"})
      add("joint_origins." + o.joint_name + ".xyz." + axis, !o.fixed.xyz);
    for (const char* axis : {"roll", "pitch", "yaw"})
      add("joint_origins." + o.joint_name + ".rpy." + axis, !o.fixed.rpy);
  }
  size_ = static_cast<int>(names_.size());
  free_position_.assign(size_, -1);
  for (int i = 0; i < size_; ++i)
    if (free_[i]) {
      free_position_[i] = static_cast<int>(free_index_.size());
      free_index_.push_back(i);
    }
}

namespace {

// The sensor group whose predictions a θ block shapes most directly. A
// joint-origin correction moves markers and tendon anchors alike; it is
// counted with the markers, whose fit it mostly is.
SensorGroup groupShaped(ThetaBlock b) {
  switch (b) {
    case ThetaBlock::kJointSensor: return SensorGroup::kJoint;
    case ThetaBlock::kTendonSensor: return SensorGroup::kTendon;
    case ThetaBlock::kMocapRotation:
    case ThetaBlock::kMocapTranslation:
    case ThetaBlock::kMarker:
    case ThetaBlock::kJointOrigin: break;
  }
  return SensorGroup::kMarker;
}

}  // namespace

int ThetaSpace::freeInGroup(SensorGroup g) const {
  int n = 0;
  for (int i : free_index_) {
    n += groupShaped(entry(i).block) == g;
  }
  return n;
}

ThetaEntry ThetaSpace::entry(int i) const {
  if (i < kTranslationOffset) return {ThetaBlock::kMocapRotation, 0, i};
  if (i < markerOffset(0)) return {ThetaBlock::kMocapTranslation, 0, i - kTranslationOffset};
  if (i < joint_offset_) return {ThetaBlock::kMarker, (i - 6) / 3, (i - 6) % 3};
  if (i < tendon_offset_)
    return {ThetaBlock::kJointSensor, (i - joint_offset_) / 2, (i - joint_offset_) % 2};
  if (i < origin_offset_)
    return {ThetaBlock::kTendonSensor, (i - tendon_offset_) / 2, (i - tendon_offset_) % 2};
  return {ThetaBlock::kJointOrigin, (i - origin_offset_) / 6, (i - origin_offset_) % 6};
}

double ThetaSpace::priorStd(int i) const {
  if (i < origin_offset_) return 0.0;
  const OriginPrior& p = sensors_->origin_prior;
  return (i - origin_offset_) % 6 < 3 ? p.xyz : p.rpy;
}

SensorParameters ThetaSpace::plus(const SensorParameters& theta,
                                  const Eigen::VectorXd& delta) const {
  SensorParameters out = theta;
  const Eigen::Vector3d w = delta.segment<3>(kRotationOffset);
  if (w.norm() > 0)
    out.mocap.rotation =
        (Eigen::Quaterniond(Eigen::AngleAxisd(w.norm(), w.normalized())) * theta.mocap.rotation)
            .normalized();
  out.mocap.translation += delta.segment<3>(kTranslationOffset);
  for (size_t m = 0; m < out.marker_position.size(); ++m)
    out.marker_position[m] += delta.segment<3>(markerOffset(static_cast<int>(m)));
  for (size_t s = 0; s < out.joint_sensor.size(); ++s) {
    out.joint_sensor[s].gain += delta[jointOffset(static_cast<int>(s))];
    out.joint_sensor[s].bias += delta[jointOffset(static_cast<int>(s)) + 1];
  }
  for (size_t s = 0; s < out.tendon_sensor.size(); ++s) {
    out.tendon_sensor[s].gain += delta[tendonOffset(static_cast<int>(s))];
    out.tendon_sensor[s].bias += delta[tendonOffset(static_cast<int>(s)) + 1];
  }
  for (size_t c = 0; c < out.joint_origin.size(); ++c) {
    out.joint_origin[c].xyz += delta.segment<3>(originOffset(static_cast<int>(c)));
    out.joint_origin[c].rpy += delta.segment<3>(originOffset(static_cast<int>(c)) + 3);
  }
  return out;
}

SensorParameters ThetaSpace::plusFree(const SensorParameters& theta,
                                      const Eigen::VectorXd& delta) const {
  return plus(theta, expandFree(delta));
}

Eigen::VectorXd ThetaSpace::expandFree(const Eigen::VectorXd& free_values) const {
  Eigen::VectorXd full = Eigen::VectorXd::Zero(size_);
  for (size_t i = 0; i < free_index_.size(); ++i) full[free_index_[i]] = free_values[i];
  return full;
}

Eigen::VectorXd ThetaSpace::minus(const SensorParameters& a, const SensorParameters& b) const {
  Eigen::VectorXd d(size_);
  const Eigen::AngleAxisd turn((a.mocap.rotation * b.mocap.rotation.conjugate()).normalized());
  d.segment<3>(kRotationOffset) = turn.angle() * turn.axis();
  d.segment<3>(kTranslationOffset) = a.mocap.translation - b.mocap.translation;
  for (size_t m = 0; m < a.marker_position.size(); ++m)
    d.segment<3>(markerOffset(static_cast<int>(m))) = a.marker_position[m] - b.marker_position[m];
  for (size_t s = 0; s < a.joint_sensor.size(); ++s) {
    d[jointOffset(static_cast<int>(s))] = a.joint_sensor[s].gain - b.joint_sensor[s].gain;
    d[jointOffset(static_cast<int>(s)) + 1] = a.joint_sensor[s].bias - b.joint_sensor[s].bias;
  }
  for (size_t s = 0; s < a.tendon_sensor.size(); ++s) {
    d[tendonOffset(static_cast<int>(s))] = a.tendon_sensor[s].gain - b.tendon_sensor[s].gain;
    d[tendonOffset(static_cast<int>(s)) + 1] = a.tendon_sensor[s].bias - b.tendon_sensor[s].bias;
  }
  for (size_t c = 0; c < a.joint_origin.size(); ++c) {
    d.segment<3>(originOffset(static_cast<int>(c))) = a.joint_origin[c].xyz - b.joint_origin[c].xyz;
    d.segment<3>(originOffset(static_cast<int>(c)) + 3) =
        a.joint_origin[c].rpy - b.joint_origin[c].rpy;
  }
  return d;
}

double ThetaSpace::value(const SensorParameters& theta, int i) const {
  const ThetaEntry e = entry(i);
  switch (e.block) {
    case ThetaBlock::kMocapRotation: {
      const Eigen::AngleAxisd turn(theta.mocap.rotation);
      return turn.angle() * turn.axis()[e.component];
    }
    case ThetaBlock::kMocapTranslation: return theta.mocap.translation[e.component];
    case ThetaBlock::kMarker: return theta.marker_position[e.item][e.component];
    case ThetaBlock::kJointSensor:
      return e.component == 0 ? theta.joint_sensor[e.item].gain : theta.joint_sensor[e.item].bias;
    case ThetaBlock::kTendonSensor:
      return e.component == 0 ? theta.tendon_sensor[e.item].gain
                              : theta.tendon_sensor[e.item].bias;
    case ThetaBlock::kJointOrigin: {
      const OriginCorrection& o = theta.joint_origin[e.item];
      return e.component < 3 ? o.xyz[e.component] : o.rpy[e.component - 3];
    }
  }
  return 0.0;
}

Eigen::VectorXd ThetaSpace::scale(const SensorParameters& theta) const {
  // Rotations in radians and positions in metres are compared through the
  // robot's size; a gain through the typical magnitude of its own value.
  Eigen::VectorXd scale = Eigen::VectorXd::Ones(size_);
  for (int i = 0; i < 3; ++i) scale[kRotationOffset + i] = 0.1;  // ~6 degrees
  for (int i = 0; i < 3; ++i) scale[kTranslationOffset + i] = 0.1;
  for (size_t m = 0; m < sensors_->markers.size(); ++m)
    scale.segment<3>(markerOffset(static_cast<int>(m))).setConstant(0.01);
  for (size_t s = 0; s < sensors_->joint_sensors.size(); ++s) {
    const double g = std::max(std::abs(theta.joint_sensor[s].gain), 1e-3);
    scale[jointOffset(static_cast<int>(s))] = 0.1 * g;
    scale[jointOffset(static_cast<int>(s)) + 1] = 0.1 * g;  // bias ~ gain * 0.1 rad
  }
  for (size_t s = 0; s < sensors_->tendon_sensors.size(); ++s) {
    const double g = std::max(std::abs(theta.tendon_sensor[s].gain), 1e-3);
    scale[tendonOffset(static_cast<int>(s))] = 0.1 * g;
    scale[tendonOffset(static_cast<int>(s)) + 1] = 0.01 * g;
  }
  // Origin corrections: millimetres and milliradians are what machining
  // and assembly leave; 1 cm and 0.01 rad (~0.6°) compare them.
  for (size_t c = 0; c < sensors_->joint_origins.size(); ++c)
    scale.segment<6>(originOffset(static_cast<int>(c))).setConstant(0.01);
  return scale;
}

ParameterStd ThetaSpace::toParameterStd(const Eigen::VectorXd& std) const {
  ParameterStd p;
  p.mocap_rotation = std.segment<3>(kRotationOffset);
  p.mocap_translation = std.segment<3>(kTranslationOffset);
  for (size_t m = 0; m < sensors_->markers.size(); ++m)
    p.marker_position.push_back(std.segment<3>(markerOffset(static_cast<int>(m))));
  for (size_t j = 0; j < sensors_->joint_sensors.size(); ++j) {
    const int o = jointOffset(static_cast<int>(j));
    p.joint_sensor.push_back({std[o], std[o + 1]});
  }
  for (size_t j = 0; j < sensors_->tendon_sensors.size(); ++j) {
    const int o = tendonOffset(static_cast<int>(j));
    p.tendon_sensor.push_back({std[o], std[o + 1]});
  }
  for (size_t c = 0; c < sensors_->joint_origins.size(); ++c) {
    const int o = originOffset(static_cast<int>(c));
    p.joint_origin.push_back({std.segment<3>(o), std.segment<3>(o + 3)});
  }
  return p;
}

std::string ThetaSpace::ownerKey(int i) const {
  const ThetaEntry e = entry(i);
  switch (e.block) {
    case ThetaBlock::kMocapRotation: return "mocap.frame.rotation";
    case ThetaBlock::kMocapTranslation: return "mocap.frame.translation";
    case ThetaBlock::kMarker: return "markers." + sensors_->markers[e.item].name + ".position";
    case ThetaBlock::kJointOrigin:
      return "joint_origins." + sensors_->joint_origins[e.item].joint_name +
             (e.component < 3 ? ".xyz" : ".rpy");
    default: return names_[i];
  }
}

std::string ThetaSpace::ownerPhrase(int i) const {
  const ThetaEntry e = entry(i);
  const char* part = e.component == 0 ? "gain" : "bias";
  switch (e.block) {
    case ThetaBlock::kMocapRotation: return "the mocap rotation";
    case ThetaBlock::kMocapTranslation: return "the mocap translation";
    case ThetaBlock::kMarker: return "marker " + sensors_->markers[e.item].name + " position";
    case ThetaBlock::kJointSensor:
      return std::string(part) + " of " + sensors_->joint_sensors[e.item].name;
    case ThetaBlock::kTendonSensor:
      return std::string(part) + " of " + sensors_->tendon_sensors[e.item].name;
    case ThetaBlock::kJointOrigin:
      return std::string(e.component < 3 ? "origin translation" : "origin rotation") + " of " +
             sensors_->joint_origins[e.item].joint_name;
  }
  return names_[i];
}

}  // namespace stac
