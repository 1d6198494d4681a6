// ceres::GradientChecker on every cost function of the monolithic mode
// (src/methods/monolithic_costs.hpp): the marker cost (hand-written
// quaternion Jacobian, rotation block on the QuaternionManifold) and the
// scalar cost (joint sensor incl. a mimic follower, path tendon, coupling
// tendon), on a chain with a prismatic joint, a mimic follower and a fixed
// joint built here, and on data/hand24 with its seed sensors.
//
// The costs read forward kinematics from the KinematicsCache, which Ceres
// refreshes through its EvaluationCallback; GradientChecker has no callback,
// so every probe goes through RefreshingCost, which writes the probed q_t
// into the cache's matrix and recomputes FK on every evaluation. Without it
// the finite differences in q would see a frozen FK (the StaleCache test
// shows the checker then fails): the q-block check compares the analytic
// q-Jacobian with real finite differences. Negative controls corrupt one
// Jacobian entry per block and require the checker to flag that block.
#include <ceres/gradient_checker.h>
#include <ceres/manifold.h>
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "methods/monolithic_costs.hpp"
#include "stac/sensors_file.hpp"
#include "support/test_util.hpp"

namespace stac::monolithic {
namespace {

// j3 prismatic; j4 follows j2 (mimic); tip hangs off e by a fixed joint.
const char* kRobot = R"(<robot name="chain">
  <link name="base"/><link name="a"/><link name="b"/><link name="c"/><link name="d"/>
  <link name="e"/><link name="tip"/>
  <joint name="j1" type="revolute"><parent link="base"/><child link="a"/>
    <origin xyz="0 0 0.1" rpy="0.2 0 0"/><axis xyz="0 0 1"/>
    <limit lower="-2" upper="2" effort="1" velocity="1"/></joint>
  <joint name="j2" type="revolute"><parent link="a"/><child link="b"/>
    <origin xyz="0.2 0 0"/><axis xyz="0 1 1"/>
    <limit lower="-2" upper="2" effort="1" velocity="1"/></joint>
  <joint name="j3" type="prismatic"><parent link="b"/><child link="c"/>
    <origin xyz="0.1 0.05 0" rpy="0 0.3 0"/><axis xyz="1 0 0"/>
    <limit lower="-0.1" upper="0.1" effort="1" velocity="1"/></joint>
  <joint name="j4" type="revolute"><parent link="c"/><child link="d"/>
    <origin xyz="0.1 0 0"/><axis xyz="1 0 0"/>
    <limit lower="-2" upper="2" effort="1" velocity="1"/>
    <mimic joint="j2" multiplier="-0.6" offset="0.1"/></joint>
  <joint name="j5" type="continuous"><parent link="d"/><child link="e"/>
    <origin xyz="0 0.08 0.02" rpy="0.1 0 -0.4"/><axis xyz="0 1 0"/></joint>
  <joint name="tip_mount" type="fixed"><parent link="e"/><child link="tip"/>
    <origin xyz="0.06 0 0.01" rpy="0 0 0.5"/></joint>
</robot>)";

constexpr int kFrames = 3;
constexpr int kFrame = 1;  // the probed frame; the others hold unrelated q
// Entry-wise relative error allowed between the analytic and the
// finite-difference Jacobians (they agree to ~1e-10 here, see probe()).
constexpr double kPrecision = 1e-8;

// Forwards to `cost` after setting q_t = the probed q block and recomputing
// FK, as Ceres's EvaluationCallback would at a new evaluation point. With
// refresh false, FK stays at whatever the cache held (the stale control).
class RefreshingCost : public ceres::CostFunction {
 public:
  RefreshingCost(ceres::CostFunction* cost, KinematicsCache* cache, RowMatrix* q, bool refresh)
      : cost_(cost), cache_(cache), q_(q), refresh_(refresh) {
    set_num_residuals(cost->num_residuals());
    *mutable_parameter_block_sizes() = cost->parameter_block_sizes();
  }
  bool Evaluate(double const* const* p, double* r, double** jac) const override {
    if (refresh_) {
      for (int i = 0; i < q_->cols(); ++i) (*q_)(kFrame, i) = p[0][i];
      cache_->PrepareForEvaluation(jac != nullptr, true);
    }
    return cost_->Evaluate(p, r, jac);
  }

 private:
  std::unique_ptr<ceres::CostFunction> cost_;
  KinematicsCache* cache_;
  RowMatrix* q_;
  bool refresh_;
};

// A deliberately wrong Jacobian: adds `delta` to entry (row, col) of block
// `block`, for the negative controls.
class CorruptedCost : public ceres::CostFunction {
 public:
  CorruptedCost(const ceres::CostFunction* cost, int block, int row, int col, double delta)
      : cost_(cost), block_(block), row_(row), col_(col), delta_(delta) {
    set_num_residuals(cost->num_residuals());
    *mutable_parameter_block_sizes() = cost->parameter_block_sizes();
  }
  bool Evaluate(double const* const* p, double* r, double** jac) const override {
    if (!cost_->Evaluate(p, r, jac)) return false;
    if (jac && jac[block_])
      jac[block_][row_ * parameter_block_sizes()[block_] + col_] += delta_;
    return true;
  }

 private:
  const ceres::CostFunction* cost_;
  int block_, row_, col_;
  double delta_;
};

double uni(std::mt19937& rng, double a, double b) {
  return std::uniform_real_distribution<double>(a, b)(rng);
}

// A cost's parameter values and the manifolds the solver puts on them.
struct Point {
  std::vector<std::vector<double>> blocks;
  std::vector<const ceres::Manifold*> manifolds;
  std::vector<const double*> pointers() const {
    std::vector<const double*> out;
    for (const std::vector<double>& b : blocks) out.push_back(b.data());
    return out;
  }
};

// q_t, a random unit quaternion, t and d.
Point markerPoint(const RobotModel& robot, std::mt19937& rng) {
  static const ceres::QuaternionManifold kQuaternion{};
  const Eigen::VectorXd q = test::randomQ(robot, rng);
  std::normal_distribution<double> normal;
  Eigen::Vector4d quat(normal(rng), normal(rng), normal(rng), normal(rng));
  quat.normalize();
  Point pt;
  pt.blocks = {std::vector<double>(q.data(), q.data() + q.size()),
               {quat[0], quat[1], quat[2], quat[3]},
               {uni(rng, -1, 1), uni(rng, -1, 1), uni(rng, 0, 2)},
               {uni(rng, -0.08, 0.08), uni(rng, -0.08, 0.08), uni(rng, -0.08, 0.08)}};
  pt.manifolds = {nullptr, &kQuaternion, nullptr, nullptr};
  return pt;
}

// q_t and (gain, bias); gains of either sign and far from 1.
Point scalarPoint(const RobotModel& robot, std::mt19937& rng) {
  const Eigen::VectorXd q = test::randomQ(robot, rng);
  const double sign = uni(rng, 0, 1) < 0.5 ? -1 : 1;
  Point pt;
  pt.blocks = {std::vector<double>(q.data(), q.data() + q.size()),
               {sign * uni(rng, 0.5, 30), uni(rng, -1, 1)}};
  pt.manifolds = {nullptr, nullptr};
  return pt;
}

// GradientChecker's test is purely relative, so an entry whose true value
// is zero but that both sides compute as roundoff (the diagonal of -[R x]x
// in the rotation block; a tendon's column for a joint that carries all its
// anchors rigidly) reads as ~100% off. A difference below kRoundoff x the
// largest entry of the cost's Jacobians counts as none.
constexpr double kRoundoff = 1e-10;

double roundoffFloor(const ceres::GradientChecker::ProbeResults& r) {
  double largest = 0;
  for (const auto& J : r.local_jacobians)
    if (J.size()) largest = std::max(largest, J.cwiseAbs().maxCoeff());
  return kRoundoff * largest;
}

// The worst entry-wise relative error of one block (local Jacobians), as
// GradientChecker measures it, but for differences below the floor.
double blockError(const ceres::GradientChecker::ProbeResults& r, int block) {
  const auto& a = r.local_jacobians[block];
  const auto& n = r.local_numeric_jacobians[block];
  const double floor = roundoffFloor(r);
  double worst = 0;
  for (int i = 0; i < a.rows(); ++i)
    for (int j = 0; j < a.cols(); ++j) {
      const double diff = std::abs(a(i, j) - n(i, j));
      if (diff <= floor) continue;
      const double scale = std::max(std::abs(a(i, j)), std::abs(n(i, j)));
      worst = std::max(worst, (a(i, j) == 0 || n(i, j) == 0) ? diff : diff / scale);
    }
  return worst;
}

// GradientChecker's verdict at kPrecision, where a Jacobian mismatch made
// only of roundoff entries is overruled; anything else it reports (a failed
// evaluation, residuals that differ with and without Jacobians) stands.
ceres::GradientChecker::ProbeResults probe(const ceres::CostFunction& cost, const Point& pt,
                                           bool* ok) {
  // From Ceres's default 1e-2 relative initial step, Ridders left the
  // derivative of a path tendon along the prismatic joint 2.4e-7 off; from
  // 1e-3 every entry here agrees to 1e-10 of the Jacobian's scale.
  ceres::NumericDiffOptions nd;
  nd.ridders_relative_initial_step_size = 1e-3;
  ceres::GradientChecker checker(&cost, &pt.manifolds, nd);
  ceres::GradientChecker::ProbeResults results;
  *ok = checker.Probe(pt.pointers().data(), kPrecision, &results);
  if (*ok || !results.return_value ||
      results.error_log.find("bad Jacobian component") == std::string::npos)
    return results;
  *ok = true;
  for (size_t k = 0; k < pt.blocks.size(); ++k)
    *ok = *ok && blockError(results, static_cast<int>(k)) <= kPrecision;
  return results;
}

// A robot, its sensors and a cache over kFrames frames of random q.
struct Fixture {
  RobotModel robot;
  SensorSet sensors;
  RowMatrix q;
  std::unique_ptr<KinematicsCache> cache;
  std::mt19937 rng{11};

  Fixture(RobotModel r, SensorSet s) : robot(std::move(r)), sensors(std::move(s)) {
    q.resize(kFrames, robot.dof());
    for (int t = 0; t < kFrames; ++t) q.row(t) = test::randomQ(robot, rng).transpose();
    cache = std::make_unique<KinematicsCache>(robot, &q, 1);
    cache->PrepareForEvaluation(true, true);
  }
  // The cache keeps references to robot and q.
  Fixture(const Fixture&) = delete;
  Fixture& operator=(const Fixture&) = delete;

  RefreshingCost marker(int m, bool refresh = true) {
    const Eigen::Vector3d x(uni(rng, -1, 1), uni(rng, -1, 1), uni(rng, 0, 2));
    return RefreshingCost(MarkerReadingCost::Create(robot, *cache, kFrame, sensors.markers[m].link,
                                                    x, sensors.markers[m].sigma),
                          cache.get(), &q, refresh);
  }
  RefreshingCost joint(int s) {
    const JointSensorConfig& c = sensors.joint_sensors[s];
    return RefreshingCost(ScalarReadingCost::Create(robot, *cache, kFrame, &c, nullptr,
                                                    uni(rng, -1, 1), c.sigma),
                          cache.get(), &q, true);
  }
  RefreshingCost tendon(int s, bool refresh = true) {
    const TendonSensorConfig& c = sensors.tendon_sensors[s];
    return RefreshingCost(ScalarReadingCost::Create(robot, *cache, kFrame, nullptr, &c,
                                                    uni(rng, -1, 1), c.sigma),
                          cache.get(), &q, refresh);
  }
};

// Markers on base, b (before the prismatic joint), d (after the prismatic
// joint and the mimic follower), e, and tip (fixed joint); joint sensors on
// j1, j3 (prismatic) and j4 (mimic follower); a path tendon over a, c and
// tip; a coupling over j1, j4 (mimic of j2) and j5.
SensorSet chainSensors(const RobotModel& robot) {
  SensorSet s;
  for (const char* l : {"base", "b", "d", "e", "tip"}) {
    MarkerConfig m;
    m.name = std::string("m_") + l;
    m.link_name = l;
    m.link = *robot.linkIndex(l);
    m.sigma = 0.002;
    s.markers.push_back(m);
  }
  for (const char* j : {"j1", "j3", "j4"}) {
    JointSensorConfig c;
    c.name = std::string(j) + "_pot";
    c.joint_name = j;
    c.joint = *robot.movableJointIndex(j);
    c.sigma = 0.01;
    s.joint_sensors.push_back(c);
  }
  TendonSensorConfig path;
  path.name = "path";
  path.path = {{"a", *robot.linkIndex("a"), {0.02, 0.01, 0}},
               {"c", *robot.linkIndex("c"), {0.03, -0.02, 0.01}},
               {"tip", *robot.linkIndex("tip"), {0.01, 0.02, 0.02}}};
  path.sigma = 0.01;
  TendonSensorConfig coupling;
  coupling.name = "coupling";
  coupling.kind = TendonSensorConfig::Kind::kCoupling;
  coupling.coupling = {{"j1", *robot.movableJointIndex("j1"), 0.01},
                       {"j4", *robot.movableJointIndex("j4"), -0.007},
                       {"j5", *robot.movableJointIndex("j5"), 0.004}};
  coupling.sigma = 0.001;
  s.tendon_sensors = {path, coupling};
  return s;
}

Fixture chain() {
  RobotModel robot = RobotModel::fromString(kRobot);
  SensorSet sensors = chainSensors(robot);
  return Fixture(std::move(robot), std::move(sensors));
}

int qColumn(const RobotModel& robot, const char* joint) {
  return robot.movableJoints()[*robot.movableJointIndex(joint)].q_index;
}

void expectPasses(const ceres::CostFunction& cost, const Point& pt, const std::string& what) {
  bool ok = false;
  const auto r = probe(cost, pt, &ok);
  EXPECT_TRUE(ok) << what << "\n" << r.error_log;
}

TEST(MonolithicCosts, ChainHasPrismaticMimicAndFixedJoints) {
  const Fixture f = chain();
  EXPECT_EQ(f.robot.dof(), 4);  // j1, j2, j3, j5: j4 follows j2
  const MovableJoint& j4 = f.robot.movableJoints()[*f.robot.movableJointIndex("j4")];
  EXPECT_TRUE(j4.is_mimic);
  EXPECT_EQ(j4.q_index, qColumn(f.robot, "j2"));
  EXPECT_EQ(f.robot.movableJoints()[*f.robot.movableJointIndex("j3")].type,
            JointType::kPrismatic);
}

// Every block, every marker link, several random q, rotations, t and d.
TEST(MonolithicCosts, MarkerJacobiansMatchFiniteDifferences) {
  Fixture f = chain();
  const int d = *f.robot.linkIndex("d");
  for (int trial = 0; trial < 6; ++trial) {
    for (size_t m = 0; m < f.sensors.markers.size(); ++m) {
      const RefreshingCost cost = f.marker(static_cast<int>(m));
      const Point pt = markerPoint(f.robot, f.rng);
      bool ok = false;
      const auto r = probe(cost, pt, &ok);
      EXPECT_TRUE(ok) << f.sensors.markers[m].name << " trial " << trial << "\n" << r.error_log;
      // The q block is compared on real derivatives, not 0 against 0: past
      // the prismatic joint and the mimic follower every column moves the
      // marker, and both sides see it.
      if (f.sensors.markers[m].link != d) continue;
      for (const char* j : {"j1", "j2", "j3"}) {
        EXPECT_GT(r.local_jacobians[0].col(qColumn(f.robot, j)).norm(), 1e-3) << j;
        EXPECT_GT(r.local_numeric_jacobians[0].col(qColumn(f.robot, j)).norm(), 1e-3) << j;
      }
    }
  }
}

TEST(MonolithicCosts, JointSensorJacobiansMatchFiniteDifferences) {
  Fixture f = chain();
  for (int trial = 0; trial < 4; ++trial)
    for (size_t s = 0; s < f.sensors.joint_sensors.size(); ++s)
      expectPasses(f.joint(static_cast<int>(s)), scalarPoint(f.robot, f.rng),
                   f.sensors.joint_sensors[s].name);
  // The mimic follower's reading moves with its master's column alone.
  bool ok = false;
  const auto r = probe(f.joint(2), scalarPoint(f.robot, f.rng), &ok);
  ASSERT_TRUE(ok) << r.error_log;
  EXPECT_NE(r.local_numeric_jacobians[0](0, qColumn(f.robot, "j2")), 0.0);
  EXPECT_NEAR(r.local_jacobians[0].norm(),
              std::abs(r.local_jacobians[0](0, qColumn(f.robot, "j2"))), 1e-12);
}

TEST(MonolithicCosts, TendonJacobiansMatchFiniteDifferences) {
  Fixture f = chain();
  for (int trial = 0; trial < 6; ++trial)
    for (size_t s = 0; s < f.sensors.tendon_sensors.size(); ++s) {
      const Point pt = scalarPoint(f.robot, f.rng);
      bool ok = false;
      const auto r = probe(f.tendon(static_cast<int>(s)), pt, &ok);
      EXPECT_TRUE(ok) << f.sensors.tendon_sensors[s].name << "\n" << r.error_log;
      EXPECT_GT(r.local_numeric_jacobians[0].norm(), 1e-6);
    }
}

// The bundled hand: every seed sensor (paths and couplings over many joints).
TEST(MonolithicCosts, Hand24SeedSensorsMatchFiniteDifferences) {
  RobotModel robot = RobotModel::fromFile(test::dataPath("hand24.urdf"));
  SensorSet sensors = loadSensorsFile(test::dataPath("hand24_seed.yaml"), robot).sensors;
  Fixture f(std::move(robot), std::move(sensors));
  ASSERT_FALSE(f.sensors.markers.empty());
  ASSERT_FALSE(f.sensors.tendon_sensors.empty());
  for (int trial = 0; trial < 2; ++trial) {
    for (size_t m = 0; m < f.sensors.markers.size(); ++m)
      expectPasses(f.marker(static_cast<int>(m)), markerPoint(f.robot, f.rng),
                   f.sensors.markers[m].name);
    for (size_t s = 0; s < f.sensors.joint_sensors.size(); ++s)
      expectPasses(f.joint(static_cast<int>(s)), scalarPoint(f.robot, f.rng),
                   f.sensors.joint_sensors[s].name);
    for (size_t s = 0; s < f.sensors.tendon_sensors.size(); ++s)
      expectPasses(f.tendon(static_cast<int>(s)), scalarPoint(f.robot, f.rng),
                   f.sensors.tendon_sensors[s].name);
  }
}

// Negative control: a 1e-6 relative error in the largest entry of any one
// block is flagged, in that block and no other.
void expectEachBlockSensitive(const ceres::CostFunction& cost, const Point& pt,
                              const std::string& what) {
  bool ok = false;
  const auto clean = probe(cost, pt, &ok);
  ASSERT_TRUE(ok) << what << "\n" << clean.error_log;
  for (size_t k = 0; k < pt.blocks.size(); ++k) {
    Eigen::Index row, col;
    const double largest = clean.jacobians[k].cwiseAbs().maxCoeff(&row, &col);
    const CorruptedCost bad(&cost, static_cast<int>(k), static_cast<int>(row),
                            static_cast<int>(col), 1e-6 * largest);
    const auto r = probe(bad, pt, &ok);
    EXPECT_FALSE(ok) << what << ": corrupted block " << k << " passed";
    for (size_t other = 0; other < pt.blocks.size(); ++other) {
      if (other == k)
        EXPECT_GT(blockError(r, static_cast<int>(other)), kPrecision) << what << " " << k;
      else
        EXPECT_LT(blockError(r, static_cast<int>(other)), kPrecision) << what << " " << k;
    }
  }
}

TEST(MonolithicCosts, CheckerFlagsACorruptedEntryInEveryBlock) {
  Fixture f = chain();
  expectEachBlockSensitive(f.marker(3), markerPoint(f.robot, f.rng), "marker on d");
  expectEachBlockSensitive(f.joint(2), scalarPoint(f.robot, f.rng), "mimic joint sensor");
  expectEachBlockSensitive(f.tendon(0), scalarPoint(f.robot, f.rng), "path tendon");
  expectEachBlockSensitive(f.tendon(1), scalarPoint(f.robot, f.rng), "coupling tendon");
}

// Negative control for the cache: with FK frozen at the fixture's q, the
// finite differences in q see no motion (or the wrong configuration) and the
// checker must flag the q block that RefreshingCost makes pass.
TEST(MonolithicCosts, StaleCacheIsFlagged) {
  Fixture f = chain();
  const struct { const char* what; RefreshingCost cost; Point pt; } cases[] = {
      {"marker on d", f.marker(3, false), markerPoint(f.robot, f.rng)},
      {"path tendon", f.tendon(0, false), scalarPoint(f.robot, f.rng)},
      {"coupling tendon", f.tendon(1, false), scalarPoint(f.robot, f.rng)}};
  for (const auto& c : cases) {
    bool ok = true;
    const auto r = probe(c.cost, c.pt, &ok);
    EXPECT_FALSE(ok) << c.what;
    EXPECT_GT(blockError(r, 0), kPrecision) << c.what;
    EXPECT_EQ(r.local_numeric_jacobians[0].norm(), 0.0) << c.what;
  }
}

}  // namespace
}  // namespace stac::monolithic
