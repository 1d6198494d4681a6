#include "experiments/experiment.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "common/outputs.hpp"
#include "stac/simulate.hpp"
#include "stac/theta_space.hpp"

namespace stac::experiments {

BundledRobot loadBundledRobot(const std::string& data_dir, const std::string& name) {
  RobotModel robot = RobotModel::fromFile(data_dir + "/" + name + ".urdf");
  SensorsFile truth = loadSensorsFile(data_dir + "/" + name + "_truth.yaml", robot);
  SensorsFile seed = loadSensorsFile(data_dir + "/" + name + "_seed.yaml", robot);
  return BundledRobot{name, std::move(robot), std::move(truth), std::move(seed)};
}

Observations toObservations(const Log& log, const SensorSet& sensors) {
  return bindLog(log, sensors, "simulation", 1.0);
}

RowMatrix randomPoses(const RobotModel& robot, int frames, std::mt19937_64& rng) {
  const std::vector<JointRange> range = motionRanges(robot);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  RowMatrix q(frames, robot.dof());
  for (int t = 0; t < frames; ++t)
    for (int j = 0; j < robot.dof(); ++j)
      q(t, j) = range[j].lower + u(rng) * (range[j].upper - range[j].lower);
  return q;
}

ParameterScore scoreParameters(const SensorSet& sensors, const SensorParameters& est,
                               const SensorParameters& truth) {
  const ThetaSpace space(sensors);
  const Eigen::VectorXd d = space.minus(est, truth);
  ParameterScore s;
  double sum = 0;
  auto add = [&](double relative, bool diverged) {
    sum += relative;
    s.diverged += diverged ? 1 : 0;
    ++s.count;
  };
  if (!sensors.markers.empty() && !sensors.mocap_frame_fixed.translation) {
    const double dt = d.segment<3>(ThetaSpace::kTranslationOffset).norm();
    add(dt / std::max(truth.mocap.translation.norm(), 0.1), dt > 0.02);
  }
  if (!sensors.markers.empty() && !sensors.mocap_frame_fixed.rotation) {
    const double angle = d.segment<3>(ThetaSpace::kRotationOffset).norm();
    add(angle, angle > 0.1);
  }
  for (size_t m = 0; m < sensors.markers.size(); ++m) {
    if (sensors.markers[m].fixed) continue;
    const double dm = d.segment<3>(space.markerOffset(static_cast<int>(m))).norm();
    add(dm / std::max(truth.marker_position[m].norm(), 0.01), dm > 0.02);
  }
  // Gains relative, biases in the sensed quantity's unit (bias / |gain|).
  auto gainBias = [&](int o, const GainBias& t, const FixedGainBias& fixed,
                      double bias_threshold) {
    const double g = std::abs(d[o]) / std::abs(t.gain);
    if (!fixed.gain) add(g, g > 0.1);
    const double b = std::abs(d[o + 1]) / std::abs(t.gain);
    if (!fixed.bias) add(b, b > bias_threshold);
  };
  for (size_t j = 0; j < sensors.joint_sensors.size(); ++j)
    gainBias(space.jointOffset(static_cast<int>(j)), truth.joint_sensor[j],
             sensors.joint_sensors[j].fixed, 0.1);
  for (size_t j = 0; j < sensors.tendon_sensors.size(); ++j)
    gainBias(space.tendonOffset(static_cast<int>(j)), truth.tendon_sensor[j],
             sensors.tendon_sensors[j].fixed, 0.005);
  s.mean_relative_error = s.count > 0 ? sum / s.count : 0.0;
  return s;
}

double divergedAngleFraction(const RowMatrix& q_est, const RowMatrix& q_true, double threshold) {
  if (q_true.size() == 0) return 0.0;
  const auto off = ((q_est - q_true).array().abs() > threshold) || !q_est.array().isFinite();
  return static_cast<double>(off.count()) / static_cast<double>(q_true.size());
}

SensorParameters perturbedSeed(const SensorSet& sensors, const SensorParameters& truth,
                               double level, std::mt19937_64& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  auto vec = [&]() { return Eigen::Vector3d(n(rng), n(rng), n(rng)); };
  SensorParameters seed = truth;
  // Draw every number whatever is fixed, so the same rng seed perturbs a
  // parameter alike across sensor configurations.
  const Eigen::Vector3d dt = vec(), dr = vec();
  if (!sensors.mocap_frame_fixed.translation) seed.mocap.translation += 0.03 * level * dt;
  if (!sensors.mocap_frame_fixed.rotation) {
    const Eigen::Vector3d w = 0.3 * level * dr;
    if (w.norm() > 0)
      seed.mocap.rotation =
          (Eigen::Quaterniond(Eigen::AngleAxisd(w.norm(), w.normalized())) * truth.mocap.rotation)
              .normalized();
  }
  for (size_t m = 0; m < sensors.markers.size(); ++m) {
    const Eigen::Vector3d d = vec();
    if (!sensors.markers[m].fixed) seed.marker_position[m] += 0.03 * level * d;
  }
  auto gainBias = [&](GainBias* p, const FixedGainBias& fixed, double bias_unit) {
    const double dg = n(rng), db = n(rng);
    const double g = p->gain;
    if (!fixed.gain) p->gain = g * (1.0 + 0.3 * level * dg);
    if (!fixed.bias) p->bias += bias_unit * level * std::abs(g) * db;
  };
  for (size_t j = 0; j < sensors.joint_sensors.size(); ++j)
    gainBias(&seed.joint_sensor[j], sensors.joint_sensors[j].fixed, 0.3);
  for (size_t j = 0; j < sensors.tendon_sensors.size(); ++j)
    gainBias(&seed.tendon_sensor[j], sensors.tendon_sensors[j].fixed, 0.005);
  return seed;
}

std::string Table::csv() const {
  std::ostringstream o;
  auto line = [&](const std::vector<std::string>& cells) {
    for (size_t i = 0; i < cells.size(); ++i) o << (i ? "," : "") << cells[i];
    o << "\n";
  };
  line(header);
  for (const auto& r : rows) line(r);
  return o.str();
}

std::string Table::markdown() const {
  std::ostringstream o;
  auto line = [&](const std::vector<std::string>& cells) {
    o << "|";
    for (const std::string& c : cells) o << " " << c << " |";
    o << "\n";
  };
  line(header);
  o << "|";
  for (size_t i = 0; i < header.size(); ++i) o << "---|";
  o << "\n";
  for (const auto& r : rows) line(r);
  return o.str();
}

std::string fmt(double v, const char* format) {
  if (!std::isfinite(v)) return "nan";
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

void writeResult(const Context& context, const std::string& name, const std::string& content) {
  cli::writeOutput(context.out_dir + "/" + name, content);
}

}  // namespace stac::experiments
