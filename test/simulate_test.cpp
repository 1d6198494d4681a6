// simulateMotion / simulateLog: limits, coverage, noise statistics, dropout,
// outliers, determinism, and the round trip through writeLog/readLog.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <random>
#include <set>

#include "stac/log.hpp"
#include "stac/measurement.hpp"
#include "stac/robot_model.hpp"
#include "stac/sensors_file.hpp"
#include "stac/simulate.hpp"
#include "support/test_util.hpp"

namespace stac {
namespace {

// Revolute, continuous and prismatic joints, and a mimic follower whose
// limits are narrower than its master's.
const char* kRobot = R"(<robot name="sim5">
  <link name="base"/><link name="l1"/><link name="l2"/><link name="l3"/>
  <link name="l4"/><link name="l5"/><link name="tool"/>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/>
    <origin xyz="0 0 0.1"/><axis xyz="0 0 1"/><limit lower="-1.5" upper="1.5" effort="1" velocity="1"/></joint>
  <joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/>
    <origin xyz="0 0 0.05"/><axis xyz="0 1 0"/><limit lower="-0.4" upper="1.2" effort="1" velocity="1"/></joint>
  <joint name="j3" type="continuous"><parent link="l2"/><child link="l3"/>
    <origin xyz="0.25 0 0"/><axis xyz="1 0 0"/></joint>
  <joint name="j4" type="prismatic"><parent link="l3"/><child link="l4"/>
    <origin xyz="0.2 0 0"/><axis xyz="1 0 0"/><limit lower="0.0" upper="0.08" effort="1" velocity="1"/></joint>
  <joint name="j5" type="revolute"><parent link="l4"/><child link="l5"/>
    <origin xyz="0.05 0 0"/><axis xyz="0 0 1"/><limit lower="-2.0" upper="2.0" effort="1" velocity="1"/></joint>
  <joint name="j5_follower" type="revolute"><parent link="l5"/><child link="tool"/>
    <origin xyz="0.05 0 0"/><axis xyz="0 1 0"/><limit lower="-0.5" upper="0.5" effort="1" velocity="1"/>
    <mimic joint="j5" multiplier="0.5" offset="0.1"/></joint>
</robot>)";

struct Problem {
  RobotModel robot;
  SensorSet sensors;
  SensorParameters truth;
};

Problem makeProblem() {
  Problem p{RobotModel::fromString(kRobot, "sim5"), {}, {}};
  const RobotModel& r = p.robot;
  SensorSet& s = p.sensors;
  const double gains[] = {1.5, -0.8, 2.0, 40.0, 1.1};
  int i = 0;
  for (const char* j : {"j1", "j2", "j3", "j4", "j5"}) {
    JointSensorConfig c;
    c.name = std::string(j) + "_pot";
    c.joint_name = j;
    c.joint = *r.movableJointIndex(j);
    c.sigma = 0.005 * (i + 1);
    s.joint_sensors.push_back(c);
    p.truth.joint_sensor.push_back({gains[i], 0.1 * i - 0.2});
    ++i;
  }
  TendonSensorConfig cyl;
  cyl.name = "cyl";
  cyl.path = {{"l1", *r.linkIndex("l1"), {0.03, 0.02, 0.0}},
              {"l3", *r.linkIndex("l3"), {0.05, 0.0, 0.03}}};
  cyl.sigma = 0.02;
  s.tendon_sensors.push_back(cyl);
  p.truth.tendon_sensor.push_back({30.0, -1.0});
  TendonSensorConfig flex;
  flex.name = "flex";
  flex.kind = TendonSensorConfig::Kind::kCoupling;
  flex.coupling = {{"j2", *r.movableJointIndex("j2"), 0.01},
                   {"j5_follower", *r.movableJointIndex("j5_follower"), 0.02}};
  flex.sigma = 0.001;
  s.tendon_sensors.push_back(flex);
  p.truth.tendon_sensor.push_back({2.0, 0.1});
  const std::pair<const char*, const char*> markers[] = {
      {"m_base", "base"}, {"m.l2.dotted", "l2"}, {"m_tool", "tool"}};
  for (const auto& [name, link] : markers) {
    MarkerConfig m;
    m.name = name;
    m.link_name = link;
    m.link = *r.linkIndex(link);
    m.sigma = std::string(name) == "m_tool" ? 0.001 : 0.002;
    s.markers.push_back(m);
    p.truth.marker_position.push_back(Eigen::Vector3d(0.02, -0.01, 0.03));
  }
  p.truth.mocap.rotation = Eigen::Quaterniond(
      Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()));
  p.truth.mocap.translation = Eigen::Vector3d(0.5, -0.2, 1.0);
  return p;
}

bool sameValues(const RowMatrix& a, const RowMatrix& b) {
  if (a.rows() != b.rows() || a.cols() != b.cols()) return false;
  for (Eigen::Index i = 0; i < a.size(); ++i) {
    const double x = a.data()[i], y = b.data()[i];
    if (std::isnan(x) != std::isnan(y)) return false;
    if (!std::isnan(x) && x != y) return false;
  }
  return true;
}

// Noise-free predictions at every frame, laid out like the log's columns.
RowMatrix predictions(const MeasurementModel& model, const SensorParameters& theta,
                      const RowMatrix& q) {
  const SensorSet& s = model.sensors();
  const int J = static_cast<int>(s.joint_sensors.size());
  const int N = static_cast<int>(s.tendon_sensors.size());
  const int M = static_cast<int>(s.markers.size());
  RowMatrix out(q.rows(), J + N + 3 * M);
  KinematicsWorkspace ws(model.robot());
  Eigen::VectorXd pm(3 * M), pj(J), pt(N);
  for (Eigen::Index t = 0; t < q.rows(); ++t) {
    const Eigen::VectorXd qt = q.row(t).transpose();
    predictFrame(model, theta, qt, &ws, pm.data(), pj.data(), pt.data());
    out.row(t) << pj.transpose(), pt.transpose(), pm.transpose();
  }
  return out;
}

std::vector<double> columnSigmas(const SensorSet& s) {
  std::vector<double> sigma;
  for (const auto& c : s.joint_sensors) sigma.push_back(c.sigma);
  for (const auto& c : s.tendon_sensors) sigma.push_back(c.sigma);
  for (const auto& c : s.markers) sigma.insert(sigma.end(), 3, c.sigma);
  return sigma;
}

TEST(SimulateMotion, StaysInsideLimitsAndSweepsEachJointInThreeSeconds) {
  const Problem p = makeProblem();
  const std::vector<JointRange> range = motionRanges(p.robot);
  ASSERT_EQ(static_cast<int>(range.size()), p.robot.dof());
  double worst_coverage = 1.0;
  for (std::uint64_t seed = 1; seed <= 40; ++seed) {
    std::mt19937_64 rng(seed);
    const RowMatrix q = simulateMotion(p.robot, 300, 100.0, rng);
    ASSERT_EQ(q.rows(), 300);
    ASSERT_EQ(q.cols(), p.robot.dof());
    for (int j = 0; j < p.robot.dof(); ++j) {
      const double lo = range[j].lower, hi = range[j].upper, width = hi - lo;
      const double qmin = q.col(j).minCoeff(), qmax = q.col(j).maxCoeff();
      EXPECT_GE(qmin, lo + 0.05 * width - 1e-12) << p.robot.qName(j) << " seed " << seed;
      EXPECT_LE(qmax, hi - 0.05 * width + 1e-12) << p.robot.qName(j) << " seed " << seed;
      if (std::isfinite(p.robot.lowerLimits()[j])) {
        EXPECT_GE(qmin, p.robot.lowerLimits()[j]);
        EXPECT_LE(qmax, p.robot.upperLimits()[j]);
      }
      const double coverage = (qmax - qmin) / width;
      worst_coverage = std::min(worst_coverage, coverage);
      EXPECT_GE(coverage, 0.5) << p.robot.qName(j) << " seed " << seed;
      // Smooth: no jump larger than the fastest component allows at 100 Hz.
      double step = 0.0;
      for (int t = 1; t < 300; ++t) step = std::max(step, std::abs(q(t, j) - q(t - 1, j)));
      EXPECT_LT(step, 0.1 * width) << p.robot.qName(j);
      EXPECT_GT(step, 0.0) << p.robot.qName(j);
    }
  }
  RecordProperty("worst_coverage_percent", static_cast<int>(100 * worst_coverage));
}

TEST(SimulateMotion, RangesFollowLimitsContinuousJointsAndMimicFollowers) {
  const Problem p = makeProblem();
  const std::vector<JointRange> r = motionRanges(p.robot);
  ASSERT_EQ(r.size(), 5u);
  EXPECT_DOUBLE_EQ(r[0].lower, -1.5);
  EXPECT_DOUBLE_EQ(r[0].upper, 1.5);
  EXPECT_DOUBLE_EQ(r[1].lower, -0.4);
  EXPECT_DOUBLE_EQ(r[1].upper, 1.2);
  EXPECT_NEAR(r[2].lower, -M_PI, 1e-12);  // continuous
  EXPECT_NEAR(r[2].upper, M_PI, 1e-12);
  EXPECT_DOUBLE_EQ(r[3].lower, 0.0);  // prismatic
  EXPECT_DOUBLE_EQ(r[3].upper, 0.08);
  // j5 in [-2, 2], but its follower 0.5 j5 + 0.1 must stay in [-0.5, 0.5].
  EXPECT_NEAR(r[4].lower, -1.2, 1e-12);
  EXPECT_NEAR(r[4].upper, 0.8, 1e-12);
}

TEST(SimulateMotion, DoesNotDependOnTheNumberOfFrames) {
  const Problem p = makeProblem();
  std::mt19937_64 a(7), b(7);
  const RowMatrix short_q = simulateMotion(p.robot, 100, 100.0, a);
  const RowMatrix long_q = simulateMotion(p.robot, 500, 100.0, b);
  EXPECT_TRUE(sameValues(short_q, long_q.topRows(100)));
  EXPECT_EQ(a(), b());  // same number of draws
  std::mt19937_64 c(7);
  EXPECT_EQ(simulateMotion(p.robot, 0, 100.0, c).rows(), 0);
  std::mt19937_64 d(7);
  EXPECT_THROW(simulateMotion(p.robot, 10, 0.0, d), std::invalid_argument);
  EXPECT_THROW(simulateMotion(p.robot, -1, 100.0, d), std::invalid_argument);
}

TEST(SimulateLog, ColumnsFollowSpecOrderAndTimeIsFrameOverRate) {
  const Problem p = makeProblem();
  const MeasurementModel model(p.robot, p.sensors);
  SimulationOptions o;
  o.frames = 10;
  o.rate_hz = 250.0;
  const Simulation sim = simulate(model, p.truth, o);
  const Log& log = sim.data.log;
  const std::vector<std::string> expected = {
      "j1_pot", "j2_pot", "j3_pot", "j4_pot", "j5_pot", "cyl", "flex",
      "m_base.x", "m_base.y", "m_base.z", "m.l2.dotted.x", "m.l2.dotted.y",
      "m.l2.dotted.z", "m_tool.x", "m_tool.y", "m_tool.z"};
  EXPECT_EQ(log.columns, expected);
  EXPECT_EQ(log.time_name, "time");
  ASSERT_EQ(log.numFrames(), 10);
  ASSERT_EQ(log.time.size(), 10u);
  for (int t = 0; t < 10; ++t) EXPECT_DOUBLE_EQ(log.time[t], t / 250.0);
  EXPECT_EQ(sim.q.rows(), 10);
  EXPECT_TRUE(sim.data.outliers.empty());
}

TEST(SimulateLog, NoiseHasTheSensorSigmaTimesTheScale) {
  const Problem p = makeProblem();
  const MeasurementModel model(p.robot, p.sensors);
  const std::vector<double> sigma = columnSigmas(p.sensors);
  for (double k : {1.0, 2.5}) {
    SimulationOptions o;
    o.frames = 5000;
    o.noise_scale = k;
    o.seed = 3;
    const Simulation sim = simulate(model, p.truth, o);
    const RowMatrix pred = predictions(model, p.truth, sim.q);
    const RowMatrix& v = sim.data.log.values;
    ASSERT_EQ(v.cols(), static_cast<Eigen::Index>(sigma.size()));
    for (Eigen::Index c = 0; c < v.cols(); ++c) {
      const Eigen::VectorXd e = v.col(c) - pred.col(c);
      const double mean = e.mean();
      const double sd = std::sqrt((e.array() - mean).square().sum() / (e.size() - 1));
      EXPECT_NEAR(sd, k * sigma[c], 0.1 * k * sigma[c])
          << sim.data.log.columns[c] << " k=" << k;
      EXPECT_NEAR(mean, 0.0, 5.0 * k * sigma[c] / std::sqrt(double(e.size())))
          << sim.data.log.columns[c];
    }
  }
}

TEST(SimulateLog, ZeroNoiseScaleGivesTheExactPredictions) {
  const Problem p = makeProblem();
  const MeasurementModel model(p.robot, p.sensors);
  SimulationOptions o;
  o.frames = 50;
  o.noise_scale = 0.0;
  const Simulation sim = simulate(model, p.truth, o);
  EXPECT_TRUE(sameValues(sim.data.log.values, predictions(model, p.truth, sim.q)));
}

TEST(SimulateLog, DropoutBlanksWholeMarkersAtTheRequestedRate) {
  const Problem p = makeProblem();
  const MeasurementModel model(p.robot, p.sensors);
  SimulationOptions o;
  o.frames = 4000;
  o.dropout = 0.3;
  const Simulation sim = simulate(model, p.truth, o);
  const RowMatrix& v = sim.data.log.values;
  const int scalars = 7, M = 3;
  int missing = 0;
  for (int t = 0; t < o.frames; ++t) {
    for (int c = 0; c < scalars; ++c) ASSERT_TRUE(std::isfinite(v(t, c)));
    for (int m = 0; m < M; ++m) {
      const int nans = std::isnan(v(t, scalars + 3 * m)) + std::isnan(v(t, scalars + 3 * m + 1)) +
                       std::isnan(v(t, scalars + 3 * m + 2));
      ASSERT_TRUE(nans == 0 || nans == 3) << "frame " << t << " marker " << m;
      missing += nans == 3;
    }
  }
  const double fraction = double(missing) / (o.frames * M);
  EXPECT_NEAR(fraction, 0.3, 0.02);  // binomial sd ≈ 0.004

  o.dropout = 1.0;
  o.frames = 20;
  const Simulation all = simulate(model, p.truth, o);
  EXPECT_TRUE(all.data.log.values.rightCols(3 * M).array().isNaN().all());
}

TEST(SimulateLog, OutliersAreGrossRecordedAndAtTheRequestedRate) {
  const Problem p = makeProblem();
  const MeasurementModel model(p.robot, p.sensors);
  const std::vector<double> sigma = columnSigmas(p.sensors);
  SimulationOptions o;
  o.frames = 3000;
  o.outliers = 0.05;
  o.dropout = 0.2;
  o.seed = 11;
  const Simulation sim = simulate(model, p.truth, o);
  const RowMatrix pred = predictions(model, p.truth, sim.q);
  const RowMatrix& v = sim.data.log.values;
  const int scalars = 7, M = 3;

  std::set<std::pair<int, int>> recorded;  // (frame, reading index)
  for (const SimulatedOutlier& out : sim.data.outliers) {
    int reading = out.sensor;
    if (out.group == SensorGroup::kTendon) reading += 5;
    if (out.group == SensorGroup::kMarker) reading += scalars;
    EXPECT_TRUE(recorded.insert({out.frame, reading}).second);
    const std::string expected_name =
        reading < scalars ? sim.data.log.columns[reading]
                          : p.sensors.markers[out.sensor].name;
    EXPECT_EQ(out.name, expected_name);
  }
  int present = 0, gross = 0;
  for (int t = 0; t < o.frames; ++t) {
    for (int r = 0; r < scalars + M; ++r) {
      double err_sigma;  // error in units of the reading's σ
      if (r < scalars) {
        err_sigma = std::abs(v(t, r) - pred(t, r)) / sigma[r];
      } else {
        const int c = scalars + 3 * (r - scalars);
        if (std::isnan(v(t, c))) {
          EXPECT_FALSE(recorded.count({t, r})) << "a missing marker is not an outlier";
          continue;
        }
        const Eigen::Vector3d d(v(t, c) - pred(t, c), v(t, c + 1) - pred(t, c + 1),
                                v(t, c + 2) - pred(t, c + 2));
        err_sigma = d.norm() / sigma[c];
        if (recorded.count({t, r})) {
          EXPECT_GT(d.norm(), 0.04);
        }
      }
      ++present;
      if (recorded.count({t, r})) {
        ++gross;
        EXPECT_GT(err_sigma, 5.0) << "frame " << t << " reading " << r;
      } else {
        EXPECT_LT(err_sigma, 6.5) << "frame " << t << " reading " << r;
      }
    }
  }
  EXPECT_EQ(gross, static_cast<int>(sim.data.outliers.size()));
  EXPECT_NEAR(double(gross) / present, 0.05, 0.006);  // binomial sd ≈ 0.0014
}

TEST(SimulateLog, SameSeedSameDataAndOptionsDoNotReshuffleTheNoise) {
  const Problem p = makeProblem();
  const MeasurementModel model(p.robot, p.sensors);
  SimulationOptions o;
  o.frames = 300;
  o.seed = 42;
  const Simulation a = simulate(model, p.truth, o);
  const Simulation b = simulate(model, p.truth, o);
  EXPECT_TRUE(sameValues(a.q, b.q));
  EXPECT_TRUE(sameValues(a.data.log.values, b.data.log.values));

  o.seed = 43;
  const Simulation c = simulate(model, p.truth, o);
  EXPECT_FALSE(sameValues(a.q, c.q));
  EXPECT_FALSE(sameValues(a.data.log.values, c.data.log.values));

  // Turning outliers and dropout on changes only the affected readings.
  o.seed = 42;
  o.outliers = 0.1;
  o.dropout = 0.1;
  const Simulation d = simulate(model, p.truth, o);
  EXPECT_TRUE(sameValues(a.q, d.q));
  ASSERT_FALSE(d.data.outliers.empty());
  std::set<std::pair<int, std::string>> outlier;
  for (const SimulatedOutlier& out : d.data.outliers) outlier.insert({out.frame, out.name});
  const Log& la = a.data.log;
  const Log& ld = d.data.log;
  int unchanged = 0;
  for (int t = 0; t < o.frames; ++t)
    for (int c = 0; c < static_cast<int>(ld.columns.size()); ++c) {
      const double x = ld.values(t, c);
      std::string name = ld.columns[c];
      if (c >= 7) name = name.substr(0, name.rfind('.'));
      if (std::isnan(x) || outlier.count({t, name})) continue;
      EXPECT_EQ(x, la.values(t, c)) << "frame " << t << " " << ld.columns[c];
      ++unchanged;
    }
  EXPECT_GT(unchanged, o.frames * 10);
}

TEST(SimulateLog, RejectsBadOptionsAndMismatchedInputs) {
  const Problem p = makeProblem();
  const MeasurementModel model(p.robot, p.sensors);
  std::string error;
  SimulationOptions o;
  EXPECT_FALSE(o.isValid(&error));  // frames = 0
  EXPECT_NE(error.find("frames"), std::string::npos) << error;
  o.frames = 10;
  EXPECT_TRUE(o.isValid(&error)) << error;
  o.dropout = 1.5;
  EXPECT_FALSE(o.isValid(&error));
  EXPECT_NE(error.find("dropout"), std::string::npos) << error;
  o.dropout = 0.0;
  o.outliers = -0.1;
  EXPECT_FALSE(o.isValid(&error));
  EXPECT_NE(error.find("outliers"), std::string::npos) << error;
  o.outliers = 0.0;
  o.noise_scale = -1.0;
  EXPECT_FALSE(o.isValid(nullptr));
  o.noise_scale = 1.0;
  o.rate_hz = std::nan("");
  EXPECT_FALSE(o.isValid(&error));
  EXPECT_NE(error.find("rate"), std::string::npos) << error;
  EXPECT_THROW(simulate(model, p.truth, o), std::invalid_argument);
  o.rate_hz = 100.0;

  std::mt19937_64 rng(1);
  EXPECT_THROW(simulateLog(model, p.truth, RowMatrix::Zero(3, 2), o, rng),
               std::invalid_argument);
  SensorParameters wrong = p.truth;
  wrong.joint_sensor.pop_back();
  EXPECT_THROW(simulateLog(model, wrong, RowMatrix::Zero(3, p.robot.dof()), o, rng),
               std::invalid_argument);
}

TEST(SimulateLog, RoundTripsThroughWriteLogAndReadLog) {
  const Problem p = makeProblem();
  const MeasurementModel model(p.robot, p.sensors);
  SimulationOptions o;
  o.frames = 200;
  o.dropout = 0.2;
  o.outliers = 0.05;
  o.seed = 5;
  const Simulation sim = simulate(model, p.truth, o);
  test::TempDir dir;
  const std::string path = dir.file("sim.csv");
  writeLog(path, sim.data.log);
  const Log back = readLog(path);
  EXPECT_EQ(back.columns, sim.data.log.columns);
  EXPECT_EQ(back.time_name, "time");
  EXPECT_EQ(back.time, sim.data.log.time);
  EXPECT_TRUE(sameValues(back.values, sim.data.log.values));
  // And the log binds to the sensors it was simulated from.
  const Observations obs = bindLog(back, p.sensors, "<sensors>", 1.0);
  EXPECT_EQ(obs.num_frames, o.frames);
}

TEST(SimulateLog, JointAnglesLogHasTimeThenJointNamesInQOrder) {
  const Problem p = makeProblem();
  RowMatrix q(2, p.robot.dof());
  q << 0.1, 0.2, 0.3, 0.04, 0.5,  //
      -0.1, 1.0e-05, 3.0, 0.0, -0.5;
  test::TempDir dir;
  writeLog(dir.file("q.csv"), jointAnglesLog(p.robot, q, {0.0, 0.01}));
  const std::string csv = test::readFile(dir.file("q.csv"));
  EXPECT_EQ(csv.substr(0, csv.find('\n')), "time,j1,j2,j3,j4,j5");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 3);
  const Log parsed = readLog(dir.file("q.csv"));
  ASSERT_EQ(parsed.numFrames(), 2);
  EXPECT_EQ(parsed.time, (std::vector<double>{0.0, 0.01}));
  EXPECT_TRUE(sameValues(parsed.values, q));
  const Log no_time = jointAnglesLog(p.robot, q, {});
  EXPECT_FALSE(no_time.hasTime());
  EXPECT_EQ(no_time.columns, (std::vector<std::string>{"j1", "j2", "j3", "j4", "j5"}));
  EXPECT_THROW(jointAnglesLog(p.robot, q, {0.0}), std::invalid_argument);
  EXPECT_THROW(jointAnglesLog(p.robot, RowMatrix::Zero(2, 3), {}), std::invalid_argument);
}

// The bundled robots, when their files are present.
class SimulateBundled : public ::testing::TestWithParam<std::string> {};

TEST_P(SimulateBundled, ReadingsAreFiniteAndEveryJointSweepsItsRange) {
  const std::string urdf = test::dataPath(GetParam() + ".urdf");
  const std::string yaml = test::dataPath(GetParam() + "_truth.yaml");
  if (!std::ifstream(urdf) || !std::ifstream(yaml)) GTEST_SKIP() << "no data/" << GetParam();
  const RobotModel robot = RobotModel::fromFile(urdf);
  const SensorsFile truth = loadSensorsFile(yaml, robot);
  const MeasurementModel model(robot, truth.sensors);
  const std::vector<JointRange> range = motionRanges(robot);
  SimulationOptions o;
  o.frames = 300;
  for (std::uint64_t seed = 1; seed <= 3; ++seed) {
    o.seed = seed;
    const Simulation sim = simulate(model, truth.theta, o);
    EXPECT_TRUE(sim.data.log.values.allFinite());
    for (int j = 0; j < robot.dof(); ++j) {
      const double qmin = sim.q.col(j).minCoeff(), qmax = sim.q.col(j).maxCoeff();
      if (std::isfinite(robot.lowerLimits()[j])) {
        EXPECT_GE(qmin, robot.lowerLimits()[j]) << robot.qName(j);
      }
      if (std::isfinite(robot.upperLimits()[j])) {
        EXPECT_LE(qmax, robot.upperLimits()[j]) << robot.qName(j);
      }
      EXPECT_GE(qmax - qmin, 0.5 * (range[j].upper - range[j].lower)) << robot.qName(j);
    }
    const Observations obs = bindLog(sim.data.log, truth.sensors, yaml, 1.0);
    EXPECT_EQ(obs.num_frames, 300);
  }
}

INSTANTIATE_TEST_SUITE_P(Data, SimulateBundled,
                         ::testing::Values("gimbal2", "hand24", "humanoid38"));

}  // namespace
}  // namespace stac
