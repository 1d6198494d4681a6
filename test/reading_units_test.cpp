// A log's joint readings in another unit — encoder ticks about an offset, as
// raw exports give them — is the same problem: the calibration must reach
// the same answer in about as many iterations.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>

#include "support/basin_draws.hpp"

namespace stac {
namespace {

constexpr double kTicks = 652;     // a radian (~4096 a turn)
constexpr double kOffset = 2048;   // the reading at zero

// The bundled hand (24 pots, 8 tendons, 300 frames of smooth motion) with
// its pots in radians or in ticks: σ, truth gains and biases converted.
struct Hand {
  test::Robot robot = test::bundledRobot("hand24", 300);
  CalibrationResult result;
  explicit Hand(bool ticks) {
    SensorParameters truth = robot.truth.theta;
    if (ticks) {
      for (JointSensorConfig& js : robot.truth.sensors.joint_sensors) js.sigma *= kTicks;
      for (GainBias& gb : truth.joint_sensor) gb = {kTicks * gb.gain, kTicks * gb.bias + kOffset};
      robot.truth.theta = truth;
    }
    const MeasurementModel model(robot.model, robot.truth.sensors);
    const Simulation sim =
        test::simulateVariant(robot, model, truth, test::Variant::kPlain, robot.frames, 5);
    CalibrationOptions o;
    o.threads = 2;
    result = calibrate(robot.model, robot.truth.sensors, test::paperSeed(robot.truth.sensors, truth),
                       bindLog(sim.data.log, robot.truth.sensors, "hand", 1.0), o);
  }
};

// Before the pots' inverse chart turned about the mean reading and the LM
// ridge became relative to each parameter's curvature, the hand in ticks
// ran 200 iterations, "not converged" (checked).
TEST(ReadingUnits, AHandLoggedInEncoderTicksCalibratesAsInRadians) {
  const Hand radians(false), ticks(true);
  ASSERT_TRUE(radians.result.summary.converged);
  EXPECT_TRUE(ticks.result.summary.converged);
  EXPECT_LE(std::abs(ticks.result.summary.iterations - radians.result.summary.iterations), 2);
  for (size_t j = 0; j < radians.result.theta.joint_sensor.size(); ++j) {
    const GainBias r = radians.result.theta.joint_sensor[j];
    const GainBias t = ticks.result.theta.joint_sensor[j];
    const GainBias sd = radians.result.std.joint_sensor[j];
    EXPECT_NEAR(t.gain / kTicks, r.gain, 0.1 * sd.gain) << "pot " << j;
    EXPECT_NEAR((t.bias - kOffset) / kTicks, r.bias, 0.1 * sd.bias) << "pot " << j;
  }
}

}  // namespace
}  // namespace stac
