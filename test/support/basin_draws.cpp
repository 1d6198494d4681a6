#include "support/basin_draws.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "stac/theta_space.hpp"
#include "support/external_sensors.hpp"
#include "support/test_util.hpp"

namespace stac::test {
namespace {

double uni(std::mt19937_64& rng, double a, double b) {
  return a + (b - a) * std::uniform_real_distribution<double>(0, 1)(rng);
}

// 5% of the present readings replaced by gross errors as the issue draws
// them: scalar sensors ±50-200 σ, markers moved 5-30 cm.
void grossOutliers(const SensorSet& s, Log* log, std::mt19937_64& rng) {
  auto column = [&](const std::string& name) {
    for (size_t c = 0; c < log->columns.size(); ++c)
      if (log->columns[c] == name) return static_cast<int>(c);
    return -1;
  };
  auto scalar = [&](const std::string& name, double sigma) {
    const int c = column(name);
    for (int t = 0; t < log->values.rows(); ++t)
      if (!std::isnan(log->values(t, c)) && uni(rng, 0, 1) < 0.05)
        log->values(t, c) += (uni(rng, 0, 1) < 0.5 ? -1 : 1) * uni(rng, 50, 200) * sigma;
  };
  for (const auto& j : s.joint_sensors) scalar(j.name, j.sigma);
  for (const auto& j : s.tendon_sensors) scalar(j.name, j.sigma);
  for (const auto& m : s.markers) {
    const int c = column(m.name + ".x");
    for (int t = 0; t < log->values.rows(); ++t) {
      if (std::isnan(log->values(t, c)) || !(uni(rng, 0, 1) < 0.05)) continue;
      Eigen::Vector3d d(uni(rng, -1, 1), uni(rng, -1, 1), uni(rng, -1, 1));
      d = d.normalized() * uni(rng, 0.05, 0.30);
      for (int i = 0; i < 3; ++i) log->values(t, c + i) += d[i];
    }
  }
}

}  // namespace

SensorParameters randomTruth(const RobotModel& robot, const SensorSet& s,
                             const SensorParameters& base, std::mt19937_64& rng) {
  SensorParameters t = base;
  Eigen::Vector4d q(uni(rng, -1, 1), uni(rng, -1, 1), uni(rng, -1, 1), uni(rng, -1, 1));
  t.mocap.rotation = Eigen::Quaterniond(q[0], q[1], q[2], q[3]).normalized();
  t.mocap.translation = Eigen::Vector3d(uni(rng, -2, 2), uni(rng, -2, 2), uni(rng, 0, 2));
  for (size_t m = 0; m < s.markers.size(); ++m)
    if (!s.markers[m].fixed)
      t.marker_position[m] = Eigen::Vector3d(uni(rng, -0.05, 0.05), uni(rng, -0.05, 0.05),
                                             uni(rng, -0.05, 0.05));
  for (size_t j = 0; j < t.joint_sensor.size(); ++j) {
    GainBias& gb = t.joint_sensor[j];
    gb.gain = (uni(rng, 0, 1) < 0.5 ? -1 : 1) * uni(rng, 0.3, 3.0);
    gb.bias = gb.gain * uni(rng, -1, 1);
    // A linear sensor's gain per its stroke, as a rotary one's per radian:
    // per metre, a finger's 4 cm stroke would swing its reading by its
    // noise, and no log could calibrate it.
    const MovableJoint& mj = robot.movableJoints()[s.joint_sensors[j].joint];
    const double stroke = robot.upperLimits()[mj.q_index] - robot.lowerLimits()[mj.q_index];
    if (mj.type == JointType::kPrismatic && std::isfinite(stroke) && stroke > 0)
      gb.gain /= stroke;
  }
  for (auto& gb : t.tendon_sensor) {
    gb.gain = (uni(rng, 0, 1) < 0.5 ? -1 : 1) * std::abs(gb.gain) * uni(rng, 0.5, 2.0);
    gb.bias = uni(rng, -2, 2);
  }
  return t;
}

SensorParameters paperSeed(const SensorSet& s, const SensorParameters& truth) {
  SensorParameters seed = truth;
  seed.mocap = MocapFrame();
  for (size_t m = 0; m < s.markers.size(); ++m)
    if (!s.markers[m].fixed) seed.marker_position[m].setZero();
  for (size_t j = 0; j < s.joint_sensors.size(); ++j)
    if (!s.joint_sensors[j].fixed.any()) seed.joint_sensor[j] = {1.0, 0.0};
  for (size_t j = 0; j < s.tendon_sensors.size(); ++j)
    if (!s.tendon_sensors[j].fixed.any()) seed.tendon_sensor[j] = {1.0, 0.0};
  return seed;
}

bool withinReportedStd(const SensorSet& s, const SensorParameters& truth,
                       const CalibrationResult& r, std::string* why, std::vector<double>* z,
                       double k) {
  auto off = [&](double error, double sd, const std::string& what) {
    if (z && sd > 0 && std::isfinite(sd)) z->push_back(error / sd);
    const char* watch = std::getenv("STAC_BASIN_Z");  // a parameter's z, every truth
    if ((std::getenv("STAC_BASIN_DIAG") && std::abs(error) > 2.5 * sd) ||
        (watch && what.find(watch) != std::string::npos))
      std::printf("    z %.2f %s\n", error / sd, what.c_str());
    if (std::abs(error) <= k * sd) return false;
    *why = what + ": " + std::to_string(error) + " off the truth (std " + std::to_string(sd) + ")";
    return true;
  };
  const ThetaSpace space(s);
  const Eigen::VectorXd d = space.minus(r.theta, truth);
  if (off(d.segment<3>(ThetaSpace::kRotationOffset).norm(), r.std.mocap_rotation.norm(),
          "mocap rotation"))
    return false;
  for (size_t m = 0; m < s.markers.size(); ++m)
    for (int i = 0; i < 3; ++i)
      if (off(d[space.markerOffset(static_cast<int>(m)) + i], r.std.marker_position[m][i],
              "marker " + s.markers[m].name))
        return false;
  for (size_t j = 0; j < s.joint_sensors.size(); ++j) {
    const std::string n = "joint sensor " + s.joint_sensors[j].name;
    const int o = space.jointOffset(static_cast<int>(j));
    if (off(d[o], r.std.joint_sensor[j].gain, n + " gain") ||
        off(d[o + 1], r.std.joint_sensor[j].bias, n + " bias"))
      return false;
  }
  for (size_t j = 0; j < s.tendon_sensors.size(); ++j) {
    const std::string n = "tendon sensor " + s.tendon_sensors[j].name;
    const int o = space.tendonOffset(static_cast<int>(j));
    if (off(d[o], r.std.tendon_sensor[j].gain, n + " gain") ||
        off(d[o + 1], r.std.tendon_sensor[j].bias, n + " bias"))
      return false;
  }
  return true;
}

bool closeToTruth(const SensorSet& s, const SensorParameters& truth, const CalibrationResult& r,
                  std::string* why, std::vector<double>* z) {
  for (const UnidentifiableDirection& u : r.summary.unidentifiable)
    if (u.reason.find("modulo a turn") == std::string::npos) return *why = u.reason, false;
  return withinReportedStd(s, truth, r, why, z);
}

Robot bundledRobot(const std::string& name, int frames) {
  RobotModel m = RobotModel::fromFile(dataPath(name + ".urdf"));
  SensorsFile seed = loadSensorsFile(dataPath(name + "_seed.yaml"), m);
  seed.theta = loadSensorsFile(dataPath(name + "_truth.yaml"), m).theta;
  return {name, std::move(m), std::move(seed), frames};
}

Robot externalRobot(RobotModel m, int frames, unsigned layout_seed) {
  std::mt19937_64 rng(layout_seed ? layout_seed : 7);
  const std::string yaml = layout_seed ? test::randomLayoutTruthYaml(m, rng)
                                       : test::inferableTruthYaml(m, true, rng);
  SensorsFile t = parseSensorsYaml(yaml, m.name() + " sensors", m);
  const std::string name = m.name();
  return {name, std::move(m), std::move(t), frames};
}

const char* variantName(Variant v) {
  return v == Variant::kPlain      ? "plain"
         : v == Variant::kOutliers ? "outliers"
         : v == Variant::kPostures ? "postures"
                                   : "partial";
}

Simulation simulateVariant(const Robot& robot, const MeasurementModel& model,
                           const SensorParameters& truth, Variant v, int frames, int seed) {
  std::mt19937_64 rng(seed);
  Simulation sim;
  sim.q = simulateMotion(robot.model, frames, 100.0, rng);
  if (v == Variant::kPartialSwings) sim.q = test::partialSwings(robot.model, sim.q, rng);
  if (v == Variant::kPostures) sim.q = test::staticPostures(robot.model, kPostures, rng);
  SimulationOptions so;
  so.frames = static_cast<int>(sim.q.rows());
  if (v == Variant::kOutliers) so.dropout = 0.3;
  sim.data = simulateLog(model, truth, sim.q, so, rng);
  if (v == Variant::kOutliers) grossOutliers(robot.truth.sensors, &sim.data.log, rng);
  return sim;
}

BasinReplay replayBasinTruth(const Robot& robot, Variant v, int index, LossKind outlier_loss,
                             CalibrationOptions o, int noise_draw, unsigned truth_seed) {
  const SensorSet& sensors = robot.truth.sensors;
  std::mt19937_64 rng(truth_seed);  // the basin test's draw of truths (STAC_BASIN_TRUTH_SEED)
  BasinReplay out;
  for (int k = 0; k <= index; ++k)
    out.truth = randomTruth(robot.model, sensors, robot.truth.theta, rng);
  const MeasurementModel model(robot.model, sensors);
  const Simulation sim = simulateVariant(robot, model, out.truth, v, robot.frames,
                                         basinLogSeed(index, noise_draw));
  o.threads = 2;
  if (v == Variant::kOutliers) o.loss = outlier_loss;
  out.result = calibrate(robot.model, sensors, paperSeed(sensors, out.truth),
                         bindLog(sim.data.log, sensors, "truth", 1.0), o);
  return out;
}

}  // namespace stac::test
