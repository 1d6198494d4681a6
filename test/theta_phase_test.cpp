// θ-phase closed forms: exact recovery from noise-free readings at the true
// q, with missing readings, and no NaN on degenerate input.
#include <gtest/gtest.h>

#include <cmath>

#include "solve/theta_phase.hpp"
#include "support/arm_fixture.hpp"

namespace stac {
namespace {

TEST(ThetaPhase, LineFitIsExactAndSkipsMissing) {
  std::vector<double> x = {0.1, -0.4, 0.9, 1.3, -1.1}, p(5);
  for (int i = 0; i < 5; ++i) p[i] = -2.5 * x[i] + 0.75;
  p[2] = NAN;
  const LineFit f = fitGainBias(x.data(), p.data(), nullptr, 5, {1.0, 0.0});
  EXPECT_TRUE(f.gain_identifiable);
  EXPECT_NEAR(f.value.gain, -2.5, 1e-12);
  EXPECT_NEAR(f.value.bias, 0.75, 1e-12);
}

TEST(ThetaPhase, JointThatNeverMovedKeepsItsGain) {
  std::vector<double> x(10, 0.3), p(10, 1.2);
  const LineFit f = fitGainBias(x.data(), p.data(), nullptr, 10, {2.0, 0.0});
  EXPECT_FALSE(f.gain_identifiable);
  EXPECT_EQ(f.value.gain, 2.0);
  EXPECT_NEAR(f.value.bias, 1.2 - 2.0 * 0.3, 1e-12);
  std::vector<double> none(3, NAN);
  const LineFit g = fitGainBias(x.data(), none.data(), nullptr, 3, {2.0, 0.5});
  EXPECT_FALSE(g.any_data);
  EXPECT_EQ(g.value.bias, 0.5);
}

TEST(ThetaPhase, ProcrustesIsExactWithProperRotation) {
  const Eigen::Matrix3d R = Eigen::AngleAxisd(2.5, Eigen::Vector3d(1, -1, 2).normalized()).toRotationMatrix();
  const Eigen::Vector3d t(0.4, -1.0, 2.0);
  std::vector<Eigen::Vector3d> a, b;
  std::vector<double> w;
  for (int i = 0; i < 6; ++i) {
    a.push_back(Eigen::Vector3d::Random());
    b.push_back(R * a.back() + t);
    w.push_back(1.0 + i);
  }
  const auto f = procrustes(a, b, w);
  ASSERT_TRUE(f.has_value());
  EXPECT_LT((f->rotation.toRotationMatrix() - R).norm(), 1e-12);
  EXPECT_LT((f->translation - t).norm(), 1e-12);
  // Coplanar points: still a proper rotation (det = +1), not a reflection.
  for (auto& p : a) p.z() = 0;
  for (size_t i = 0; i < a.size(); ++i) b[i] = R * a[i] + t;
  const auto g = procrustes(a, b, w);
  ASSERT_TRUE(g.has_value());
  EXPECT_NEAR(g->rotation.toRotationMatrix().determinant(), 1.0, 1e-12);
  EXPECT_LT((g->rotation.toRotationMatrix() - R).norm(), 1e-10);
}

TEST(ThetaPhase, CollinearPointsAreReportedNotNaN) {
  std::vector<Eigen::Vector3d> a, b;
  for (int i = 0; i < 5; ++i) {
    a.emplace_back(i, 2.0 * i, -i);
    b.emplace_back(i + 1.0, 2.0 * i, -i);
  }
  EXPECT_FALSE(procrustes(a, b, std::vector<double>(5, 1.0)).has_value());
  EXPECT_FALSE(procrustes({a[0], a[1]}, {b[0], b[1]}, {1.0, 1.0}).has_value());
}

class ExactRecovery : public ::testing::TestWithParam<double> {};

TEST_P(ExactRecovery, ClosedFormsRecoverTruthFromNoiseFreeReadings) {
  const double dropout = GetParam();
  test::ArmProblem p = test::makeArmProblem(200, 31, 0.0, dropout);
  const MeasurementModel model(p.robot, p.sensors);
  std::vector<FrameWorkspace> ws;
  ws.emplace_back(model);
  QState state;
  state.q = p.q_true;
  // Mocap frame by Procrustes from the true marker positions, then each
  // marker by averaging from a wrong start.
  SensorParameters th = p.truth;
  for (auto& d : th.marker_position) d.setZero();
  th.mocap = MocapFrame();
  SensorParameters with_true_markers = p.truth;
  with_true_markers.mocap = MocapFrame();
  initialiseMarkerGroup(model, p.obs, state, 1, 1, &ws, &with_true_markers);
  EXPECT_LT((with_true_markers.mocap.rotation.toRotationMatrix() -
             p.truth.mocap.rotation.toRotationMatrix()).norm(), 1e-9);
  EXPECT_LT((with_true_markers.mocap.translation - p.truth.mocap.translation).norm(), 1e-9);
  const MarkerPoseCache poses = cacheMarkerPoses(model, p.q_true, 1, &ws);
  for (size_t m = 0; m < p.sensors.markers.size(); ++m) {
    const auto d = averageMarkerPosition(poses, p.obs, p.truth.mocap, static_cast<int>(m));
    ASSERT_TRUE(d.has_value());
    EXPECT_LT((*d - p.truth.marker_position[m]).norm(), 1e-9);
  }
  // The whole θ-phase from the paper's seed (free parameters only).
  SensorParameters seed = p.seed;
  ThetaPhaseOptions to;
  to.threads = 1;
  to.marker_gauss_newton_steps = 20;
  initialiseMarkerGroup(model, p.obs, state, 1, 1, &ws, &seed);
  thetaPhase(model, NoiseModel::fromSeeds(p.sensors), RobustLoss(), p.obs, state, to, &ws, &seed);
  for (size_t j = 0; j < p.sensors.joint_sensors.size(); ++j) {
    EXPECT_NEAR(seed.joint_sensor[j].gain, p.truth.joint_sensor[j].gain, 1e-9);
    EXPECT_NEAR(seed.joint_sensor[j].bias, p.truth.joint_sensor[j].bias, 1e-9);
  }
  EXPECT_NEAR(seed.tendon_sensor[0].gain, p.truth.tendon_sensor[0].gain, 1e-9);
  EXPECT_NEAR(seed.tendon_sensor[0].bias, p.truth.tendon_sensor[0].bias, 1e-9);
  for (size_t m = 0; m < p.sensors.markers.size(); ++m)
    EXPECT_LT((seed.marker_position[m] - p.truth.marker_position[m]).norm(), 1e-9);
  EXPECT_LT((seed.mocap.translation - p.truth.mocap.translation).norm(), 1e-9);
}

INSTANTIATE_TEST_SUITE_P(Dropout, ExactRecovery, ::testing::Values(0.0, 0.3));

TEST(ThetaPhase, MarkerNeverSeenKeepsItsValue) {
  test::ArmProblem p = test::makeArmProblem(50, 2, 0.0);
  for (int t = 0; t < p.obs.num_frames; ++t)
    for (int i = 0; i < 3; ++i) p.obs.marker(t, 3 * 2 + i) = NAN;  // m_l2b never seen
  const MeasurementModel model(p.robot, p.sensors);
  std::vector<FrameWorkspace> ws;
  ws.emplace_back(model);
  QState state;
  state.q = p.q_true;
  SensorParameters th = p.seed;
  th.marker_position[2] = Eigen::Vector3d(0.01, 0.02, 0.03);
  const MarkerPoseCache poses = cacheMarkerPoses(model, p.q_true, 1, &ws);
  EXPECT_FALSE(averageMarkerPosition(poses, p.obs, p.truth.mocap, 2).has_value());
  initialiseMarkerGroup(model, p.obs, state, 2, 1, &ws, &th);
  thetaPhase(model, NoiseModel::fromSeeds(p.sensors), RobustLoss(), p.obs, state,
             ThetaPhaseOptions(), &ws, &th);
  EXPECT_TRUE(th.marker_position[2].allFinite());
  EXPECT_LT((th.marker_position[2] - Eigen::Vector3d(0.01, 0.02, 0.03)).norm(), 1e-9);
}

}  // namespace
}  // namespace stac
