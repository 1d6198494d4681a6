// Uses the installed library end to end through its private dependencies:
// a URDF (urdfdom, tinyxml), a sensors YAML (yaml-cpp), forward kinematics
// (KDL-built model), compares a marker with stac::runtime's map, and
// calibrates through the public headers alone.
#include <cmath>
#include <cstdio>

#include "stac/calibrate.hpp"
#include "stac/kinematics.hpp"
#include "stac/robot_model.hpp"
#include "stac/runtime/sensor_maps.hpp"
#include "stac/sensors_file.hpp"
#include "stac/simulate.hpp"

int main() {
  const char* urdf = R"(<robot name="two">
  <link name="base"/><link name="l1"/><link name="l2"/>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/>
    <origin xyz="0 0 0.1"/><axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  <joint name="j2" type="prismatic"><parent link="l1"/><child link="l2"/>
    <origin xyz="0.2 0 0"/><axis xyz="1 0 0"/><limit lower="0" upper="0.1" effort="1" velocity="1"/></joint>
</robot>)";
  const char* yaml = R"(mocap:
  frame: {translation: [0.1, 0.2, 0.3], rpy: [0.0, 0.0, 0.5]}
  markers:
    - {name: tip, link: l2, position: [0.05, 0.0, 0.0]}
joint_sensors:
  - {name: j1_pot, joint: j1, gain: 2.0, bias: 0.5}
)";
  try {
    const stac::RobotModel robot = stac::RobotModel::fromString(urdf, "consumer.urdf");
    const stac::SensorsFile file = stac::parseSensorsYaml(yaml, "consumer.yaml", robot);
    stac::KinematicsWorkspace ws(robot);
    Eigen::VectorXd q(2);
    q << 0.3, 0.05;
    stac::forwardKinematics(robot, q, &ws);
    const int link = file.sensors.markers[0].link;
    const Eigen::Vector3d x = stac::runtime::markerPosition(
        file.theta.mocap.rotation, file.theta.mocap.translation, ws.link_pose[link],
        file.theta.marker_position[0]);
    // By hand: the tip is 0.2 + 0.05 + 0.05 = 0.3 m along l1's x, at z 0.1,
    // turned by 0.3 rad (j1) then 0.5 rad (mocap yaw), then shifted.
    const Eigen::Vector3d expected(0.1 + 0.3 * std::cos(0.8), 0.2 + 0.3 * std::sin(0.8), 0.4);
    const double p = stac::runtime::jointReading(q[0], file.theta.joint_sensor[0].gain,
                                                 file.theta.joint_sensor[0].bias);
    if ((x - expected).norm() > 1e-12 || std::abs(p - 1.1) > 1e-12) {
      std::fprintf(stderr, "mismatch: x = %g %g %g, p = %g\n", x.x(), x.y(), x.z(), p);
      return 1;
    }
    // The calibration API from the installed headers alone: readings
    // simulated from the file's values, calibrated from them, a summary.
    stac::SimulationOptions so;
    so.frames = 100;
    const stac::Simulation sim = stac::simulate(stac::MeasurementModel(robot, file.sensors),
                                                file.theta, so);
    const stac::Observations obs = stac::bindLog(sim.data.log, file.sensors, "consumer.yaml", 1.0);
    stac::CalibrationOptions co;
    co.threads = 1;
    co.max_iterations = 3;
    const stac::CalibrationResult r = stac::calibrate(robot, file.sensors, file.theta, obs, co);
    if (r.summary.frames != 100 || stac::briefReport(robot, file.theta, r).empty()) {
      std::fprintf(stderr, "calibration: %d frames\n", r.summary.frames);
      return 1;
    }
    std::printf("stac consumer: %d joints, marker at %.3f %.3f %.3f\n", robot.dof(), x.x(),
                x.y(), x.z());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}
