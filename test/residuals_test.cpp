// Per-reading residual samples (residuals.hpp) against the calibration's own
// numbers: the "before" sample reproduces summary.before_rms (same frames,
// same q fit), the "after" sample summary.after_rms and every sensor's RMS.
#include <gtest/gtest.h>

#include <cmath>

#include "stac/calibrate.hpp"
#include "stac/log.hpp"
#include "stac/residuals.hpp"
#include "stac/sensors_file.hpp"
#include "support/test_util.hpp"

namespace stac {
namespace {

class Residuals : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    robot_ = new RobotModel(RobotModel::fromFile(test::dataPath("gimbal2.urdf")));
    sf_ = new SensorsFile(loadSensorsFile(test::dataPath("gimbal2_seed.yaml"), *robot_));
    obs_ = new Observations(bindLog(readLog(test::dataPath("gimbal2_example.csv")), sf_->sensors,
                                    "gimbal2_seed.yaml", 1.0));
    CalibrationOptions o;
    o.threads = 2;
    q_ = new RowMatrix;
    result_ = new CalibrationResult(calibrate(*robot_, sf_->sensors, sf_->theta, *obs_, o, q_));
  }
  static void TearDownTestSuite() {
    delete result_;
    delete q_;
    delete obs_;
    delete sf_;
    delete robot_;
  }
  static RobotModel* robot_;
  static SensorsFile* sf_;
  static Observations* obs_;
  static RowMatrix* q_;
  static CalibrationResult* result_;
};
RobotModel* Residuals::robot_ = nullptr;
SensorsFile* Residuals::sf_ = nullptr;
Observations* Residuals::obs_ = nullptr;
RowMatrix* Residuals::q_ = nullptr;
CalibrationResult* Residuals::result_ = nullptr;

TEST_F(Residuals, BeforeSampleIsTheSummarysBeforeRms) {
  ResidualSampleOptions o;
  o.threads = 2;
  const ResidualSample before = sampleResiduals(*robot_, sf_->sensors, sf_->theta, *obs_, nullptr, o);
  for (SensorGroup g : {SensorGroup::kMarker, SensorGroup::kTendon}) {
    const double expected = result_->summary.before_rms[static_cast<int>(g)];
    EXPECT_GT(expected, 0.1);  // a poor seed: large residuals
    EXPECT_NEAR(before.rms(g), expected, 1e-9 * expected) << groupName(g);
  }
  EXPECT_TRUE(before.magnitude[static_cast<int>(SensorGroup::kJoint)].empty());
}

TEST_F(Residuals, AfterSampleIsTheSummarysAfterRmsAndPerSensorRms) {
  ResidualSampleOptions o;
  o.threads = 1;
  const ResidualSample after =
      sampleResiduals(*robot_, result_->sensors, result_->theta, *obs_, q_, o);
  ASSERT_EQ(static_cast<int>(after.frames.size()), obs_->num_frames);  // 300 <= 1000
  for (SensorGroup g : {SensorGroup::kMarker, SensorGroup::kTendon}) {
    const double expected = result_->summary.after_rms[static_cast<int>(g)];
    EXPECT_NEAR(after.rms(g), expected, 1e-9 * expected) << groupName(g);
  }
  // Per sensor, from the sample's sensor indices.
  const int g = static_cast<int>(SensorGroup::kMarker);
  for (size_t m = 0; m < result_->marker_residual.size(); ++m) {
    double sse = 0;
    int n = 0;
    for (size_t k = 0; k < after.magnitude[g].size(); ++k)
      if (after.sensor[g][k] == static_cast<int>(m)) sse += std::pow(after.magnitude[g][k], 2), ++n;
    EXPECT_EQ(n, result_->marker_residual[m].count);
    EXPECT_NEAR(std::sqrt(sse / n), result_->marker_residual[m].rms, 1e-12);
  }
  // Thread count changes nothing.
  o.threads = 2;
  const ResidualSample again =
      sampleResiduals(*robot_, result_->sensors, result_->theta, *obs_, q_, o);
  for (int k = 0; k < kNumSensorGroups; ++k) {
    EXPECT_EQ(again.magnitude[k], after.magnitude[k]);
    EXPECT_EQ(again.sensor[k], after.sensor[k]);
  }
}

TEST_F(Residuals, SpreadFramesAndValidation) {
  ResidualSampleOptions o;
  o.max_frames = 30;
  const ResidualSample s = sampleResiduals(*robot_, result_->sensors, result_->theta, *obs_, q_, o);
  ASSERT_EQ(s.frames.size(), 30u);
  EXPECT_EQ(s.frames.front(), 0);
  EXPECT_GE(s.frames.back(), obs_->num_frames - obs_->num_frames / 30);
  // Every present reading of the sampled frames, once.
  size_t markers = 0, tendons = 0;
  for (int t : s.frames) {
    for (int m = 0; m < static_cast<int>(obs_->marker.cols()) / 3; ++m)
      markers += !std::isnan(obs_->marker(t, 3 * m));
    for (int k = 0; k < obs_->tendon.cols(); ++k) tendons += !std::isnan(obs_->tendon(t, k));
  }
  EXPECT_EQ(s.magnitude[0].size(), markers);
  EXPECT_EQ(s.magnitude[2].size(), tendons);
  o.max_frames = 0;
  EXPECT_THROW(sampleResiduals(*robot_, sf_->sensors, sf_->theta, *obs_, nullptr, o),
               std::invalid_argument);
  o.max_frames = 10;
  const RowMatrix wrong(3, robot_->dof());
  EXPECT_THROW(sampleResiduals(*robot_, sf_->sensors, sf_->theta, *obs_, &wrong, o),
               std::invalid_argument);
}

}  // namespace
}  // namespace stac
