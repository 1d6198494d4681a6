#include "solve/whole_turns.hpp"

#include <algorithm>
#include <cmath>

namespace stac {

std::vector<TurnSensor> turnSensors(const MeasurementModel& model, const Eigen::VectorXd& lower,
                                    const Eigen::VectorXd& upper, const std::vector<bool>& frozen) {
  const RobotModel& robot = model.robot();
  std::vector<TurnSensor> out;
  const auto& sensors = model.sensors().joint_sensors;
  for (size_t s = 0; s < sensors.size(); ++s) {
    const MovableJoint& mj = robot.movableJoints()[sensors[s].joint];
    if (mj.type == JointType::kPrismatic || mj.multiplier == 0) continue;
    const int j = mj.q_index;
    if (!frozen.empty() && frozen[j]) continue;
    if (!(upper[j] - lower[j] > 2 * M_PI)) continue;  // ∞ for a continuous joint
    out.push_back({static_cast<int>(s), j, mj.multiplier, mj.offset});
  }
  return out;
}

int turnsToFit(const TurnSensor& sensor, const GainBias& map, double sigma, double reading,
               double q) {
  const double per_turn = 2 * M_PI * map.gain * sensor.multiplier;  // reading units
  if (!std::isfinite(reading) || !(std::abs(per_turn) >= kTurnInSigma * sigma)) return 0;
  const double predicted = map.gain * (sensor.multiplier * q + sensor.offset) + map.bias;
  const double turns = std::round((reading - predicted) / per_turn);
  if (!(std::abs(turns) >= 1 && std::abs(turns) <= kMaxTurns)) return 0;
  if (!(std::abs(predicted + turns * per_turn - reading) <= kTurnFitSigma * sigma)) return 0;
  return static_cast<int>(turns);
}

}  // namespace stac
