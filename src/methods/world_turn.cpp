// The world's half turn with a limb's first joint (see world_turn.hpp).
#include "methods/world_turn.hpp"

#include <algorithm>

namespace stac {
namespace {
// Axes this parallel (|a × b|) are one line where their points are.
constexpr double kParallel = 1e-6;
}  // namespace

double distanceFromLine(const Eigen::Vector3d& x, const Eigen::Vector3d& p,
                        const Eigen::Vector3d& d) {
  const Eigen::Vector3d v = x - p;
  return (v - v.dot(d) * d).norm();
}

std::vector<Eigen::Vector3d> baseMarkerPoints(const MeasurementModel& model,
                                              const SensorParameters& theta,
                                              const KinematicsWorkspace& ws) {
  const RobotModel& robot = model.robot();
  const SensorSet& sensors = model.sensors();
  std::vector<Eigen::Vector3d> out;
  for (size_t m = 0; m < sensors.markers.size(); ++m)
    if (robot.supportingJoints(sensors.markers[m].link).empty())
      out.push_back(ws.link_pose[sensors.markers[m].link] * theta.marker_position[m]);
  return out;
}

std::vector<int> limbRoots(const RobotModel& robot) {
  std::vector<int> out;
  for (int j = 0; j < robot.dof(); ++j) {
    const int mj = robot.qJoints()[j];
    if (robot.supportingJoints(robot.movableJoints()[mj].child_link).size() == 1)
      out.push_back(j);
  }
  return out;
}

std::vector<int> worldTurnColumns(const MeasurementModel& model, const SensorParameters& theta) {
  const RobotModel& robot = model.robot();
  std::vector<int> out;
  if (model.sensors().mocap_frame_fixed.any()) return out;
  // A limb's first joint turns about a line fixed in the base: its axis
  // at any pose is its axis at zero.
  KinematicsWorkspace ws(robot);
  forwardKinematics(robot, Eigen::VectorXd::Zero(robot.dof()), &ws);
  const std::vector<Eigen::Vector3d> base = baseMarkerPoints(model, theta, ws);
  const std::vector<int> roots = limbRoots(robot);
  for (int j : roots) {
    const int mj = robot.qJoints()[j];
    const Eigen::Vector3d p = ws.joint_origin[mj];
    const Eigen::Vector3d d = ws.joint_axis[mj].normalized();
    const auto pins = [&](const Eigen::Vector3d& x) {
      return distanceFromLine(x, p, d) >= kLineSpan;
    };
    const auto otherLimb = [&](int k) {
      const int mk = robot.qJoints()[k];
      return k != j && (ws.joint_axis[mk].normalized().cross(d).norm() > kParallel ||
                        pins(ws.joint_origin[mk]));
    };
    if (std::none_of(base.begin(), base.end(), pins) &&
        std::none_of(roots.begin(), roots.end(), otherLimb))
      out.push_back(j);
  }
  return out;
}

std::vector<MinimumMove> worldTurnMoves(const MeasurementModel& model,
                                        const std::vector<PotGuess>& guesses,
                                        const SensorParameters& theta) {
  const std::vector<int> columns = worldTurnColumns(model, theta);
  std::vector<MinimumMove> moves;
  for (int i = 0; i < static_cast<int>(guesses.size()); ++i)
    if (!guesses[i].bias_held &&
        std::find(columns.begin(), columns.end(), guesses[i].column) != columns.end()) {
      MinimumMove move{{}, {i}, {}};
      move.world_turn = true;
      moves.push_back(std::move(move));
    }
  return moves;
}

}  // namespace stac
