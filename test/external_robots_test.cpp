// STAC on real public robots nobody here wrote (../shared/robots, passed in
// by STAC_ROBOTS_DIR): the sensors a user would log without a sensors file —
// a pot on every joint of q named after the joint, a marker on the root link
// and on every link a joint of q moves, named after the link — with a random
// truth (gains of both signs, biases, markers a few cm off the link origin,
// a rotated and shifted mocap frame), calibrated from the inferred seed
// (gains 1, biases 0, markers at link origins, identity frame). The right
// minimum fits every group at its noise level; a wrong basin is off by
// centimetres and tenths of a volt. Robots with more than 12 joints are
// left to the long basin test.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <sstream>

#include "stac/calibrate.hpp"
#include "stac/sensors_file.hpp"
#include "stac/simulate.hpp"
#include "support/external_sensors.hpp"
#include "support/test_util.hpp"

namespace stac {
namespace {

// `max_swing` > 0: the log moves each joint at most that far either side of
// the middle of its range. Real logs rarely sweep a UR arm's ±2π joints; the
// wide basin must not assume they do.
void calibrateInferred(double max_swing) {
  const std::vector<std::string> urdfs = test::externalUrdfs();
  if (urdfs.empty()) GTEST_SKIP() << "STAC_ROBOTS_DIR not set";
  int tested = 0;
  for (const std::string& urdf : urdfs) {
    const RobotModel robot = RobotModel::fromFile(urdf);
    if (robot.dof() > 12) continue;
    for (std::uint64_t seed : {1u, 2u, 3u}) {
      SCOPED_TRACE(urdf + " truth " + std::to_string(seed) + " swing " +
                   std::to_string(max_swing));
      std::mt19937_64 rng(seed);
      const SensorsFile truth =
          parseSensorsYaml(test::inferableTruthYaml(robot, false, rng), "truth", robot);
      const MeasurementModel model(robot, truth.sensors);
      SimulationOptions so;
      so.frames = 600;
      so.seed = seed;
      Simulation sim = simulate(model, truth.theta, so);
      if (max_swing > 0) {
        const std::vector<JointRange> range = motionRanges(robot);
        for (int j = 0; j < robot.dof(); ++j) {
          const double mid = 0.5 * (range[j].lower + range[j].upper);
          const double half = 0.5 * (range[j].upper - range[j].lower);
          const double coverage = std::min(1.0, max_swing / half);
          sim.q.col(j) = (mid + coverage * (sim.q.col(j).array() - mid)).matrix();
        }
        std::mt19937_64 noise_rng(seed + 100);
        sim.data = simulateLog(model, truth.theta, sim.q, so, noise_rng);
      }
      // What stac_calib does without --sensors.
      const SensorsFile inferred = inferSensorsFromLog(sim.data.log, robot);
      const Observations obs = bindLog(sim.data.log, inferred.sensors, "log", 1.0);
      CalibrationOptions options;
      options.threads = 2;
      const CalibrationResult r = calibrate(robot, inferred.sensors, inferred.theta, obs, options);
      EXPECT_LT(r.summary.after_rms[0], 2.0 * 0.002 * std::sqrt(3.0)) << "markers: wrong basin";
      EXPECT_LT(r.summary.after_rms[1], 2.0 * 0.01) << "pots: wrong basin";
      EXPECT_FALSE(r.summary.suspect()) << r.summary.verdict.front();
      // Gains are identifiable whatever the gauge: each within 5 of its
      // reported standard deviations (or 1%: a gain the markers pin down
      // well may be off by less than its noise but more than 5 std of a
      // slightly optimistic std).
      for (size_t j = 0; j < truth.sensors.joint_sensors.size(); ++j) {
        const std::string& name = truth.sensors.joint_sensors[j].name;
        for (size_t k = 0; k < inferred.sensors.joint_sensors.size(); ++k) {
          if (inferred.sensors.joint_sensors[k].name != name) continue;
          const double g = truth.theta.joint_sensor[j].gain;
          EXPECT_NEAR(r.theta.joint_sensor[k].gain, g,
                      std::max(0.01 * std::abs(g), 5.0 * r.std.joint_sensor[k].gain))
              << name << " (std " << r.std.joint_sensor[k].gain << ")";
        }
      }
    }
    ++tested;
  }
  EXPECT_GT(tested, 0) << "no external robot with at most 12 joints";
}

TEST(ExternalRobots, InferredSensorsCalibrateFromThePaperSeeding) { calibrateInferred(0); }

TEST(ExternalRobots, LogsSwingingJointsAtMost1p5RadCalibrateToo) { calibrateInferred(1.5); }

}  // namespace
}  // namespace stac
