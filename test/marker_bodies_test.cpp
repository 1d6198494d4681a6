// Virtual points of one tracked rigid body (solve/marker_bodies.hpp): found
// by their constant mutual distances, and counted in the variance
// adaptation as the one pose error they carry.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "solve/marker_bodies.hpp"
#include "stac/calibrate.hpp"
#include "support/arm_fixture.hpp"

namespace stac {
namespace {

MarkerConfig marker(const std::string& name, const std::string& link) {
  MarkerConfig m;
  m.name = name;
  m.link_name = link;
  return m;
}

// `frames` frames of points moved rigidly (points[k] turned and shifted per
// frame), plus `noise` metres of independent noise per coordinate.
Observations movedPoints(const std::vector<Eigen::Vector3d>& points, int frames, double noise,
                         unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> n(0.0, 1.0);
  Observations obs;
  obs.num_frames = frames;
  obs.marker.resize(frames, 3 * static_cast<int>(points.size()));
  for (int t = 0; t < frames; ++t) {
    const Eigen::Matrix3d R =
        Eigen::AngleAxisd(0.3 * t, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
    const Eigen::Vector3d shift(0.1 * t, -0.05 * t, 0.5);
    for (size_t k = 0; k < points.size(); ++k)
      for (int i = 0; i < 3; ++i)
        obs.marker(t, 3 * k + i) = (R * points[k] + shift)[i] + noise * n(rng);
  }
  return obs;
}

const std::vector<Eigen::Vector3d> kSquare = {
    {0.05, 0.05, 0}, {-0.05, 0.05, 0}, {-0.05, -0.05, 0}, {0.05, -0.05, 0.01}};

TEST(MarkerBodies, VirtualPointsOfOneLinkFormOneBody) {
  SensorSet s;
  for (int k = 0; k < 4; ++k) s.markers.push_back(marker("p" + std::to_string(k), "hand"));
  s.markers.push_back(marker("elsewhere", "forearm"));
  std::vector<Eigen::Vector3d> points = kSquare;
  points.push_back({0.2, 0, 0});  // moved with them, but on another link
  const MarkerBodies b = findMarkerBodies(s, movedPoints(points, 20, 0.0, 1));
  ASSERT_EQ(b.rank.size(), 1u);
  EXPECT_EQ(b.rank[0], 6);
  EXPECT_EQ(b.size[0], 4);
  EXPECT_EQ(b.body_of_marker, (std::vector<int>{0, 0, 0, 0, -1}));
  // 12 rows carry 6 dims; fewer points present, fewer rows per dim.
  EXPECT_DOUBLE_EQ(b.rowsPerDim(0, 4), 2.0);
  EXPECT_DOUBLE_EQ(b.rowsPerDim(0, 3), 1.5);
  EXPECT_DOUBLE_EQ(b.rowsPerDim(0, 2), 6.0 / 5.0);
  EXPECT_DOUBLE_EQ(b.rowsPerDim(0, 1), 1.0);
}

TEST(MarkerBodies, PhysicalMarkersWithTheirOwnNoiseAreNoBody) {
  SensorSet s;
  for (int k = 0; k < 4; ++k) s.markers.push_back(marker("m" + std::to_string(k), "hand"));
  // 20 µm of noise, a very good mocap's: distances vary by ~30 µm.
  EXPECT_TRUE(findMarkerBodies(s, movedPoints(kSquare, 50, 20e-6, 2)).empty());
  // Without noise they are one body again (the tolerance is not the test).
  EXPECT_FALSE(findMarkerBodies(s, movedPoints(kSquare, 50, 0.0, 2)).empty());
}

TEST(MarkerBodies, PointsOnALineHaveFiveDims) {
  SensorSet s;
  for (int k = 0; k < 3; ++k) s.markers.push_back(marker("p" + std::to_string(k), "wand"));
  const MarkerBodies b = findMarkerBodies(
      s, movedPoints({{0, 0, 0}, {0.1, 0.1, 0}, {0.25, 0.25, 0}}, 10, 0.0, 3));
  ASSERT_EQ(b.rank.size(), 1u);
  EXPECT_EQ(b.rank[0], 5);
  EXPECT_DOUBLE_EQ(b.rowsPerDim(0, 3), 9.0 / 5.0);
}

TEST(MarkerBodies, TooFewCommonFramesProveNothing) {
  SensorSet s;
  for (int k = 0; k < 2; ++k) s.markers.push_back(marker("p" + std::to_string(k), "hand"));
  Observations obs = movedPoints({kSquare[0], kSquare[1]}, 10, 0.0, 4);
  for (int t = 2; t < 10; ++t) obs.marker(t, 0) = obs.marker(t, 1) = obs.marker(t, 2) = NAN;
  EXPECT_TRUE(findMarkerBodies(s, obs).empty());  // 2 frames read both
  obs = movedPoints({kSquare[0], kSquare[1]}, 10, 0.0, 4);
  for (int t = 3; t < 10; ++t) obs.marker(t, 0) = obs.marker(t, 1) = obs.marker(t, 2) = NAN;
  EXPECT_FALSE(findMarkerBodies(s, obs).empty());  // 3 do
}

// The 4-DoF test arm with a tracked body of four virtual points on its last
// link instead of its link markers: each frame's readings of the body are
// its true points moved by one small rigid motion, the base marker reads
// with independent noise. The body is a regular tetrahedron and the motion
// has as much variance per dim of the points' 12 rows in rotation as in
// translation, so that each of the 6 dims the rows carry holds its share
// of the noise (the count assumes so). The q_t take up to 4 of the 6;
// counted against 12 independent rows, the marker σ came out at 0.88-0.90
// of the noise the readings hold (0.97-0.98 counted as one pose; noise
// draws 3, 11, 29, 47).
TEST(MarkerBodies, TheMarkerSigmaOfATrackedBodyMatchesItsNoise) {
  test::ArmProblem p = test::makeArmProblem(600, 5);
  SensorSet s = p.sensors;
  SensorParameters truth = p.truth, seed = p.seed;
  s.markers.resize(1);  // m_base, fixed: the mocap rotation's gauge
  truth.marker_position.resize(1);
  seed.marker_position.resize(1);
  const double radius = 0.05, shift_sigma = 0.0015;
  const double turn_sigma = shift_sigma * std::sqrt(1.5) / radius;  // Σ|δθ×d|² = 4 Σ|δp|²
  const Eigen::Vector3d centre(0.08, 0.0, 0.0);
  std::vector<Eigen::Vector3d> body;
  for (const Eigen::Vector3d& v : {Eigen::Vector3d(1, 1, 1), Eigen::Vector3d(1, -1, -1),
                                   Eigen::Vector3d(-1, 1, -1), Eigen::Vector3d(-1, -1, 1)})
    body.push_back(centre + radius * v.normalized());
  for (size_t k = 0; k < body.size(); ++k) {
    MarkerConfig m = marker("b" + std::to_string(k), "l4");
    m.link = *p.robot.linkIndex("l4");
    m.sigma = p.sensors.markers[0].sigma;
    m.fixed = k == 0;  // j4's bias against the points on its link
    s.markers.push_back(m);
    truth.marker_position.push_back(body[k]);
    seed.marker_position.push_back(k == 0 ? body[k] : Eigen::Vector3d::Zero());
  }
  const MeasurementModel model(p.robot, s);
  std::mt19937 rng(29);
  Observations obs;
  test::simulateReadings(model, truth, p.q_true, 1.0, 0.0, rng, &obs);
  std::normal_distribution<double> n(0.0, 1.0);
  KinematicsWorkspace kin(p.robot);
  Eigen::VectorXd pm(3 * s.markers.size()), pj(s.joint_sensors.size()), pt(s.tendon_sensors.size());
  double sse = 0;  // of every marker reading, per coordinate
  for (int t = 0; t < obs.num_frames; ++t) {
    predictFrame(model, truth, p.q_true.row(t).transpose(), &kin, pm.data(), pj.data(), pt.data());
    for (int i = 0; i < 3; ++i) sse += std::pow(obs.marker(t, i) - pm[i], 2);
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    for (int k = 1; k <= 4; ++k) centre += pm.segment<3>(3 * k) / 4;
    const Eigen::Vector3d shift = shift_sigma * Eigen::Vector3d(n(rng), n(rng), n(rng));
    const Eigen::Vector3d turn = turn_sigma * Eigen::Vector3d(n(rng), n(rng), n(rng));
    const Eigen::Matrix3d R = Eigen::AngleAxisd(turn.norm(), turn.normalized()).toRotationMatrix();
    for (int k = 1; k <= 4; ++k) {
      const Eigen::Vector3d y = centre + shift + R * (pm.segment<3>(3 * k) - centre);
      obs.marker.block<1, 3>(t, 3 * k) = y.transpose();
      sse += (y - pm.segment<3>(3 * k)).squaredNorm();
    }
  }
  const double noise = std::sqrt(sse / (15.0 * obs.num_frames));
  CalibrationOptions o;
  o.threads = 2;
  const CalibrationResult r = calibrate(p.robot, s, seed, obs, o);
  ASSERT_FALSE(r.summary.suspect()) << r.summary.verdict[0];
  EXPECT_NEAR(r.summary.group_sigma[0] / noise, 1.0, 0.06) << noise;
}

}  // namespace
}  // namespace stac
