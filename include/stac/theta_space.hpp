// θ as one vector: the single owner of its layout (paper §II: θ gathers every
// sensor's parameters). Every solver, the uncertainty, the outputs and the
// experiments go through this class, so adding a parameter type touches this
// class and that type's own model, nothing else.
//
// Layout, in entries (the order of the sensors file):
//   [mocap rotation δ (3) | mocap translation (3) | marker positions (3 each) |
//    joint sensors (gain, bias) | tendon sensors (gain, bias) |
//    joint-origin corrections (x, y, z, roll, pitch, yaw each)]
// The rotation's three entries are a tangent vector: θ ⊕ δ turns the mocap
// frame by exp([δ]×) on the left (SO(3) is a manifold, not a vector space);
// every other entry adds.
//
//   const ThetaSpace space(sensors);              // sensors must outlive it
//   SensorParameters next = space.plus(theta, delta);
//   Eigen::VectorXd d = space.minus(estimate, truth);   // estimate = truth ⊕ d
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "stac/calibration.hpp"
#include "stac/sensors.hpp"

namespace stac {

// What one θ entry belongs to.
enum class ThetaBlock {
  kMocapRotation,
  kMocapTranslation,
  kMarker,
  kJointSensor,
  kTendonSensor,
  kJointOrigin
};

struct ThetaEntry {
  ThetaBlock block = ThetaBlock::kMocapRotation;
  int item = 0;       // marker or sensor index within its block (0 for the frame)
  int component = 0;  // x/y/z (0..2), 0 = gain, 1 = bias, or x/y/z/roll/pitch/yaw (0..5)
};

class ThetaSpace {
 public:
  explicit ThetaSpace(const SensorSet& sensors);

  const SensorSet& sensors() const { return *sensors_; }
  int size() const { return size_; }

  // Offsets of each parameter block.
  static constexpr int kRotationOffset = 0;
  static constexpr int kTranslationOffset = 3;
  int markerOffset(int m) const { return 6 + 3 * m; }
  int jointOffset(int s) const { return joint_offset_ + 2 * s; }
  int tendonOffset(int s) const { return tendon_offset_ + 2 * s; }
  int originOffset(int c) const { return origin_offset_ + 6 * c; }
  // The joint-origin corrections' links (SensorSet::joint_origins order),
  // what setOriginCorrections() takes.
  const std::vector<int>& originLinks() const { return origin_links_; }
  // The prior std of entry i (0: no prior; only joint-origin entries have one).
  double priorStd(int i) const;
  ThetaEntry entry(int i) const;

  // Human names, e.g. "markers.m_head.position.x", "joint_sensors.p.bias".
  const std::vector<std::string>& names() const { return names_; }
  // False where the parameter is held fixed (or there are no markers, for
  // the mocap frame).
  const std::vector<bool>& free() const { return free_; }
  // The free entries in order, and each entry's position among them (-1:
  // fixed): the columns of every reduced system.
  const std::vector<int>& freeIndex() const { return free_index_; }
  const std::vector<int>& freePosition() const { return free_position_; }
  int freeSize() const { return static_cast<int>(free_index_.size()); }
  // The free entries that shape one sensor group's predictions (the mocap
  // frame and markers for kMarker): the degrees of freedom θ spends on it.
  int freeInGroup(SensorGroup g) const;

  // θ ⊕ δ, δ over all entries (size()).
  SensorParameters plus(const SensorParameters& theta, const Eigen::VectorXd& delta) const;
  // θ ⊕ δ, δ over the free entries only (freeSize()).
  SensorParameters plusFree(const SensorParameters& theta, const Eigen::VectorXd& delta) const;
  // The δ with b ⊕ δ = a (the rotation's entries: log(R_a R_bᵀ)).
  Eigen::VectorXd minus(const SensorParameters& a, const SensorParameters& b) const;
  // The value of entry i (a rotation entry: that component of log R).
  double value(const SensorParameters& theta, int i) const;
  // Scatters a vector over the free entries into one over all (0 elsewhere).
  Eigen::VectorXd expandFree(const Eigen::VectorXd& free_values) const;

  // A typical magnitude per entry, to compare parameters of different units
  // (metres, radians, volts) when judging identifiability or change.
  Eigen::VectorXd scale(const SensorParameters& theta) const;

  // Per-entry standard deviations into the per-sensor structure.
  ParameterStd toParameterStd(const Eigen::VectorXd& std) const;

  // The parameter an entry belongs to, for messages: its key
  // ("mocap.frame.rotation", "markers.m1.position", "joint_sensors.p.bias")
  // and a phrase ("the mocap rotation", "marker m1 position", "bias of p").
  std::string ownerKey(int i) const;
  std::string ownerPhrase(int i) const;

 private:
  const SensorSet* sensors_;
  int joint_offset_ = 0, tendon_offset_ = 0, origin_offset_ = 0, size_ = 0;
  std::vector<int> origin_links_;
  std::vector<std::string> names_;
  std::vector<bool> free_;
  std::vector<int> free_index_, free_position_;
};

}  // namespace stac
