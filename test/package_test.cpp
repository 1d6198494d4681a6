// stac::runtime (include/stac/runtime/sensor_maps.hpp) computes what the
// library predicts: every reading of a noise-free simulation is recomputed
// from the true q with the runtime's maps (FK for link poses only), and the
// inverses recover q and the lengths. The installed package itself is
// tested by ctest's package_* tests (cmake/StacInstall.cmake).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "stac/kinematics.hpp"
#include "stac/measurement.hpp"
#include "stac/robot_model.hpp"
#include "stac/runtime/sensor_maps.hpp"
#include "stac/sensors_file.hpp"
#include "stac/simulate.hpp"
#include "support/arm_files.hpp"

namespace stac {
namespace {

namespace rt = stac::runtime;

// The arm's truth plus a coupling tendon over j2 and j4.
std::string armSensorsWithCoupling() {
  return std::string(test::kArmTruth) +
         "  - name: flex\n"
         "    gain: 2.5\n"
         "    bias: 0.3\n"
         "    sigma: 0.01\n"
         "    coupling: {j2: 0.009, j4: -0.012}\n";
}

TEST(RuntimeMaps, AgreeWithTheLibrarysPredictions) {
  const RobotModel robot = RobotModel::fromString(test::kArmUrdf, "arm.urdf");
  const SensorsFile file = parseSensorsYaml(armSensorsWithCoupling(), "arm.yaml", robot);
  const MeasurementModel model(robot, file.sensors);
  SimulationOptions options;
  options.frames = 20;
  options.noise_scale = 0.0;
  options.seed = 7;
  const Simulation sim = simulate(model, file.theta, options);
  const Log& log = sim.data.log;
  auto column = [&](const std::string& name) {
    for (std::size_t c = 0; c < log.columns.size(); ++c)
      if (log.columns[c] == name) return static_cast<int>(c);
    ADD_FAILURE() << "no column " << name;
    return 0;
  };

  KinematicsWorkspace ws(robot);
  for (int f = 0; f < options.frames; ++f) {
    const Eigen::VectorXd q = sim.q.row(f).transpose();
    forwardKinematics(robot, q, &ws);

    for (std::size_t i = 0; i < file.sensors.joint_sensors.size(); ++i) {
      const JointSensorConfig& s = file.sensors.joint_sensors[i];
      const GainBias& gb = file.theta.joint_sensor[i];
      const double angle = ws.movable_q[s.joint];
      const double p = log.values(f, column(s.name));
      EXPECT_NEAR(rt::jointReading(angle, gb.gain, gb.bias), p, 1e-12) << s.name;
      EXPECT_NEAR(rt::jointAngle(p, gb.gain, gb.bias), angle, 1e-12) << s.name;
      const rt::LinearSensor<double> sensor = {gb.gain, gb.bias};
      EXPECT_NEAR(sensor.value(p), angle, 1e-12) << s.name;
    }

    for (std::size_t i = 0; i < file.sensors.tendon_sensors.size(); ++i) {
      const TendonSensorConfig& s = file.sensors.tendon_sensors[i];
      const GainBias& gb = file.theta.tendon_sensor[i];
      double length = 0;
      if (s.kind == TendonSensorConfig::Kind::kPath) {
        Eigen::Matrix3Xd anchors(3, s.path.size());
        std::vector<Eigen::Vector3d> points;
        for (std::size_t k = 0; k < s.path.size(); ++k) {
          anchors.col(k) = ws.link_pose[s.path[k].link] * s.path[k].point;
          points.push_back(anchors.col(k));
        }
        length = rt::pathLength(anchors);
        EXPECT_EQ(rt::pathLength(points.data(), points.size()), length);
      } else {
        Eigen::VectorXd c(s.coupling.size()), angles(s.coupling.size());
        for (std::size_t j = 0; j < s.coupling.size(); ++j) {
          c[j] = s.coupling[j].coefficient;
          angles[j] = ws.movable_q[s.coupling[j].joint];
        }
        length = rt::couplingLength(c, angles);
        EXPECT_NEAR(rt::couplingLength(c.data(), angles.data(), s.coupling.size()), length,
                    1e-15);
      }
      const double p = log.values(f, column(s.name));
      EXPECT_NEAR(rt::tendonReading(length, gb.gain, gb.bias), p, 1e-10) << s.name;
      EXPECT_NEAR(rt::tendonLength(p, gb.gain, gb.bias), length, 1e-12) << s.name;
    }

    const rt::MocapFrame<double> frame = {file.theta.mocap.rotation,
                                          file.theta.mocap.translation};
    for (std::size_t m = 0; m < file.sensors.markers.size(); ++m) {
      const MarkerConfig& mk = file.sensors.markers[m];
      const Eigen::Vector3d& d = file.theta.marker_position[m];
      const Eigen::Vector3d seen(log.values(f, column(mk.name + ".x")),
                                 log.values(f, column(mk.name + ".y")),
                                 log.values(f, column(mk.name + ".z")));
      const Eigen::Isometry3d& T = ws.link_pose[mk.link];
      EXPECT_LT((rt::markerPosition(frame, T, d) - seen).norm(), 1e-12) << mk.name;
      EXPECT_LT((rt::markerInLink(frame, T, seen) - d).norm(), 1e-12) << mk.name;
    }
  }
}

TEST(RuntimeMaps, FloatInstantiations) {
  const rt::LinearSensor<float> pot = {-1.5f, 0.4f};
  EXPECT_NEAR(pot.value(pot.reading(0.3f)), 0.3f, 1e-6f);
  EXPECT_NEAR(rt::jointAngle(1.0f, 2.0f, 0.5f), 0.25f, 1e-7f);
  const Eigen::Vector3f pts[2] = {Eigen::Vector3f(0, 0, 0), Eigen::Vector3f(0, 3, 4)};
  EXPECT_NEAR(rt::pathLength(pts, 2), 5.0f, 1e-6f);
  EXPECT_EQ(rt::pathLength(pts, 1), 0.0f);
  const Eigen::Quaternionf R(Eigen::AngleAxisf(0.3f, Eigen::Vector3f::UnitX()));
  const Eigen::Vector3f t(1, 2, 3), d(0.1f, 0.2f, 0.3f);
  const Eigen::Isometry3f T = Eigen::Isometry3f::Identity();
  EXPECT_LT((rt::markerInLink(R, t, T, rt::markerPosition(R, t, T, d)) - d).norm(), 1e-6f);
}

}  // namespace
}  // namespace stac
