// Every analytic Jacobian of the residual assembly against central
// differences: with respect to q and to θ, for every sensor type (marker,
// joint sensor incl. a mimic follower, tendon path and coupling), plain and
// robustified.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "stac/log.hpp"
#include "stac/measurement.hpp"
#include "solve/q_phase.hpp"
#include "solve/schur.hpp"
#include "support/test_util.hpp"

namespace stac {
namespace {

const char* kRobot = R"(<robot name="r">
  <link name="base"/><link name="a"/><link name="b"/><link name="c"/><link name="d"/>
  <joint name="j1" type="revolute"><parent link="base"/><child link="a"/>
    <origin xyz="0 0 0.1" rpy="0.2 0 0"/><axis xyz="0 0 1"/>
    <limit lower="-2" upper="2" effort="1" velocity="1"/></joint>
  <joint name="j2" type="revolute"><parent link="a"/><child link="b"/>
    <origin xyz="0.2 0 0"/><axis xyz="0 1 1"/>
    <limit lower="-2" upper="2" effort="1" velocity="1"/></joint>
  <joint name="j3" type="prismatic"><parent link="b"/><child link="c"/>
    <origin xyz="0.1 0.05 0"/><axis xyz="1 0 0"/>
    <limit lower="-0.1" upper="0.1" effort="1" velocity="1"/></joint>
  <joint name="j4" type="revolute"><parent link="c"/><child link="d"/>
    <origin xyz="0.1 0 0"/><axis xyz="1 0 0"/>
    <limit lower="-2" upper="2" effort="1" velocity="1"/>
    <mimic joint="j2" multiplier="-0.6" offset="0.1"/></joint>
</robot>)";

struct Scene {
  RobotModel robot = RobotModel::fromString(kRobot);
  SensorSet sensors;
  SensorParameters theta;
  Observations obs;
  Scene() {
    std::mt19937 rng(3);
    auto uni = [&](double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); };
    for (const char* l : {"b", "d", "base"}) {
      MarkerConfig m;
      m.name = std::string("m_") + l;
      m.link_name = l;
      m.link = *robot.linkIndex(l);
      m.sigma = 0.002;
      sensors.markers.push_back(m);
      theta.marker_position.emplace_back(uni(-0.05, 0.05), uni(-0.05, 0.05), uni(-0.05, 0.05));
    }
    for (const char* j : {"j1", "j4"}) {  // j4 is a mimic follower
      JointSensorConfig s;
      s.name = std::string(j) + "_pot";
      s.joint_name = j;
      s.joint = *robot.movableJointIndex(j);
      s.sigma = 0.01;
      sensors.joint_sensors.push_back(s);
      theta.joint_sensor.push_back({uni(-2, 2), uni(-1, 1)});
    }
    TendonSensorConfig path;
    path.name = "path";
    path.path = {{"a", *robot.linkIndex("a"), {0.02, 0.01, 0}},
                 {"b", *robot.linkIndex("b"), {0.03, -0.02, 0.01}},
                 {"d", *robot.linkIndex("d"), {0.01, 0.02, 0.02}}};
    path.sigma = 0.01;
    TendonSensorConfig coupling;
    coupling.name = "coupling";
    coupling.kind = TendonSensorConfig::Kind::kCoupling;
    coupling.coupling = {{"j1", *robot.movableJointIndex("j1"), 0.01},
                         {"j4", *robot.movableJointIndex("j4"), -0.007}};
    coupling.sigma = 0.001;
    sensors.tendon_sensors = {path, coupling};
    theta.tendon_sensor = {{uni(10, 30), uni(-1, 1)}, {uni(-30, -10), uni(-1, 1)}};
    // Joint-origin corrections on every joint (revolute, prismatic, mimic
    // follower): markers and the path's anchors downstream of them.
    for (const char* j : {"j1", "j2", "j3", "j4"}) {
      JointOriginConfig c;
      c.joint_name = j;
      c.link = robot.movableJoints()[*robot.movableJointIndex(j)].child_link;
      sensors.joint_origins.push_back(c);
      OriginCorrection o;
      o.xyz = Eigen::Vector3d(uni(-0.01, 0.01), uni(-0.01, 0.01), uni(-0.01, 0.01));
      o.rpy = Eigen::Vector3d(uni(-0.3, 0.3), uni(-0.3, 0.3), uni(-0.3, 0.3));
      theta.joint_origin.push_back(o);
    }
    theta.mocap.rotation = Eigen::Quaterniond(Eigen::AngleAxisd(1.1, Eigen::Vector3d(1, 2, 3).normalized()));
    theta.mocap.translation = Eigen::Vector3d(0.3, -0.2, 1.0);
    obs.num_frames = 1;
    obs.marker = RowMatrix::Zero(1, 9);
    obs.joint = RowMatrix::Zero(1, 2);
    obs.tendon = RowMatrix::Zero(1, 2);
    for (int i = 0; i < 9; ++i) obs.marker(0, i) = uni(-1, 1);
    for (int i = 0; i < 2; ++i) obs.joint(0, i) = uni(-1, 1), obs.tendon(0, i) = uni(-1, 1);
  }
};

// All whitened residuals of the frame stacked, in reading order.
Eigen::VectorXd residuals(const MeasurementModel& model, const SensorParameters& theta,
                          const RobustLoss& loss, const Observations& obs,
                          const Eigen::VectorXd& q) {
  FrameWorkspace ws(model);
  FrameOptions eo;
  eo.jacobians = false;
  evaluateFrame(model, theta, NoiseModel::fromSeeds(model.sensors()), loss,
                frameReadings(obs, 0), q, eo, &ws);
  std::vector<double> r;
  for (int i = 0; i < ws.count; ++i)
    for (int k = 0; k < ws.readings[i].rows; ++k) r.push_back(ws.readings[i].r[k]);
  return Eigen::Map<Eigen::VectorXd>(r.data(), r.size());
}

void checkJacobians(const RobustLoss& loss, double obs_scale) {
  Scene s;
  s.obs.marker *= obs_scale;
  const MeasurementModel model(s.robot, s.sensors);
  const NoiseModel noise = NoiseModel::fromSeeds(s.sensors);
  std::mt19937 rng(5);
  for (int trial = 0; trial < 5; ++trial) {
    const Eigen::VectorXd q = test::randomQ(s.robot, rng);
    FrameWorkspace ws(model);
    FrameOptions eo;
    eo.theta_jacobians = true;
    evaluateFrame(model, s.theta, noise, loss, frameReadings(s.obs, 0), q, eo, &ws);
    // Assemble dense analytic Jacobians.
    const Eigen::VectorXd r0 = residuals(model, s.theta, loss, s.obs, q);
    Eigen::MatrixXd Jq = Eigen::MatrixXd::Zero(r0.size(), model.dof());
    Eigen::MatrixXd Jt = Eigen::MatrixXd::Zero(r0.size(), model.thetaSpace().size());
    int row = 0;
    for (int i = 0; i < ws.count; ++i) {
      const ReadingJacobian& rj = ws.readings[i];
      for (int k = 0; k < rj.rows; ++k, ++row) {
        for (size_t c = 0; c < rj.q_cols->size(); ++c) Jq(row, (*rj.q_cols)[c]) = rj.Jq(k, c);
        for (int c = 0; c < rj.theta_count; ++c) Jt(row, rj.theta_index[c]) += rj.Jtheta(k, c);
      }
    }
    const double h = 1e-6;
    for (int j = 0; j < model.dof(); ++j) {
      Eigen::VectorXd qp = q, qm = q;
      qp[j] += h;
      qm[j] -= h;
      const Eigen::VectorXd fd = (residuals(model, s.theta, loss, s.obs, qp) -
                                  residuals(model, s.theta, loss, s.obs, qm)) / (2 * h);
      EXPECT_LT((fd - Jq.col(j)).norm(), 1e-6 * std::max(1.0, fd.norm())) << "q" << j;
    }
    const std::vector<int>& all = model.thetaSpace().freeIndex();
    for (int k : all) {
      Eigen::VectorXd step = Eigen::VectorXd::Zero(all.size());
      step[k] = h;
      const Eigen::VectorXd fd =
          (residuals(model, model.thetaSpace().plusFree(s.theta, step), loss, s.obs, q) -
           residuals(model, model.thetaSpace().plusFree(s.theta, -step), loss, s.obs, q)) / (2 * h);
      EXPECT_LT((fd - Jt.col(k)).norm(), 1e-6 * std::max(1.0, fd.norm()))
          << model.thetaSpace().names()[k];
    }
  }
}

TEST(Measurement, JacobiansMatchCentralDifferences) { checkJacobians(RobustLoss(), 1.0); }

TEST(Measurement, RobustifiedJacobiansMatchCentralDifferences) {
  // Large residuals put many readings in the loss's robust region.
  checkJacobians(RobustLoss(LossKind::kHuber, 2.0), 1.0);
  checkJacobians(RobustLoss(LossKind::kCauchy, 1.5), 1.0);
}

TEST(Measurement, RobustCostIsHalfTheSumOfRho) {
  Scene s;
  const MeasurementModel model(s.robot, s.sensors);
  const RobustLoss huber(LossKind::kHuber, 2.0);
  FrameWorkspace ws(model);
  FrameOptions eo;
  const Eigen::VectorXd q = Eigen::VectorXd::Zero(model.dof());
  const double cost = evaluateFrame(model, s.theta, NoiseModel::fromSeeds(s.sensors), huber,
                                    frameReadings(s.obs, 0), q, eo, &ws);
  double sum = 0, check = 0;
  for (int i = 0; i < ws.count; ++i) {
    double rho[3];
    huber.evaluate(ws.readings[i].s, rho);
    sum += rho[0];
    check += ws.readings[i].r.head(ws.readings[i].rows).squaredNorm();
  }
  EXPECT_NEAR(cost, 0.5 * sum, 1e-9 * sum);
  EXPECT_NEAR(check, sum, 1e-9 * sum);  // the robustified residual's norm² is ρ
}


// Each group's share of the dof q_t takes against tr(J_g H⁻¹ J_gᵀ) from the
// dense Jacobian, plain and robustified, with a marker missing too; with
// `body`, markers 0 and 1 as virtual points of one tracked body
// (marker_bodies.hpp), whose leverage counts rowsPerDim times.
void checkGroupLeverage(const RobustLoss& loss, bool drop_marker, bool body = false) {
  Scene s;
  if (drop_marker) s.obs.marker.row(0).head(3).setConstant(std::nan(""));
  const MeasurementModel model(s.robot, s.sensors);
  FrameWorkspace ws(model);
  FrameOptions eo;
  const int n = model.dof();
  const Eigen::VectorXd q = Eigen::VectorXd::LinSpaced(n, 0.1, 0.4);
  evaluateFrame(model, s.theta, NoiseModel::fromSeeds(s.sensors), loss, frameReadings(s.obs, 0),
                q, eo, &ws);
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(3 * ws.count, n);
  std::vector<int> group;
  std::vector<bool> in_body;
  MarkerBodies bodies;
  if (body) {
    bodies.body_of_marker.assign(s.sensors.markers.size(), -1);
    bodies.body_of_marker[0] = bodies.body_of_marker[1] = 0;
    bodies.rank = {6};
    bodies.size = {2};
  }
  int present = 0;
  for (int i = 0; i < ws.count; ++i) {
    const ReadingJacobian& rj = ws.readings[i];
    const bool member = body && rj.group == SensorGroup::kMarker && rj.sensor < 2;
    present += member;
    for (int r = 0; r < rj.rows; ++r) {
      for (size_t a = 0; a < rj.q_cols->size(); ++a)
        J(static_cast<int>(group.size()), (*rj.q_cols)[a]) += rj.Jq(r, a);
      group.push_back(static_cast<int>(rj.group));
      in_body.push_back(member);
    }
  }
  J.conservativeResize(static_cast<int>(group.size()), n);
  Eigen::MatrixXd H = J.transpose() * J;
  const double eps = 1e-12 * std::max(1.0, H.diagonal().maxCoeff());
  const Eigen::MatrixXd Hinv = (H + eps * Eigen::MatrixXd::Identity(n, n)).inverse();
  double want[kNumSensorGroups] = {0, 0, 0};
  const double per_dim = body ? bodies.rowsPerDim(0, present) : 1.0;
  for (int r = 0; r < J.rows(); ++r)
    want[group[r]] += (in_body[r] ? per_dim : 1.0) * J.row(r) * Hinv * J.row(r).transpose();

  Eigen::MatrixXd Hws(n, n), Linv(n, n);
  Eigen::VectorXd g(n);
  accumulateNormalEquations(ws, &Hws, &g);
  double got[kNumSensorGroups] = {0, 0, 0};
  addGroupLeverage(ws, bodies, &Hws, &Linv, got);
  for (int k = 0; k < kNumSensorGroups; ++k) {
    EXPECT_GT(want[k], 0.05) << "group " << k;  // every group takes a real share
    EXPECT_NEAR(got[k], want[k], 1e-7) << "group " << k;
  }
}

TEST(Measurement, GroupLeverageMatchesTheDenseHatMatrix) {
  checkGroupLeverage(RobustLoss(), false);
  checkGroupLeverage(RobustLoss(), true);
  checkGroupLeverage(RobustLoss(LossKind::kHuber, 0.5), false);
  // Two points of one body: 6 rows, 5 dims (a lone point left: 3 and 3).
  checkGroupLeverage(RobustLoss(), false, true);
  checkGroupLeverage(RobustLoss(), true, true);
}

// The sandwich's meat: Σ_t g̃_t g̃_tᵀ over frames, each g̃_t being the reduced
// gradient of frame t alone (so one frame's meat is g gᵀ).
TEST(Schur, ScoreOuterProductSumsEachFramesReducedGradient) {
  Scene s;
  Observations two = s.obs;
  two.num_frames = 2;
  std::mt19937 rng(8);
  auto uni = [&](double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); };
  two.marker.conservativeResize(2, Eigen::NoChange);
  two.joint.conservativeResize(2, Eigen::NoChange);
  two.tendon.conservativeResize(2, Eigen::NoChange);
  for (int i = 0; i < 9; ++i) two.marker(1, i) = uni(-1, 1);
  for (int i = 0; i < 2; ++i) two.joint(1, i) = uni(-1, 1), two.tendon(1, i) = uni(-1, 1);
  const MeasurementModel model(s.robot, s.sensors);
  const NoiseModel noise = NoiseModel::fromSeeds(s.sensors);
  RowMatrix q(2, model.dof());
  for (int t = 0; t < 2; ++t)
    for (int j = 0; j < model.dof(); ++j) q(t, j) = uni(-0.5, 0.5);
  std::vector<FrameWorkspace> ws(2, FrameWorkspace(model));
  for (const RobustLoss& loss : {RobustLoss(), RobustLoss(LossKind::kHuber, 2.0)}) {
    const int nf = model.thetaSpace().freeSize();
    ASSERT_GT(nf, 10);
    Eigen::MatrixXd want = Eigen::MatrixXd::Zero(nf, nf);
    for (int t = 0; t < 2; ++t) {
      const Observations one = selectFrames(two, {t});
      const RowMatrix qt = q.row(t);
      const ReducedSystem rs = reduceOntoTheta(model, s.theta, noise, loss, one, qt, 0.0, true, 2,
                                               &ws);
      want += rs.g * rs.g.transpose();
    }
    Eigen::MatrixXd got;
    const ReducedSystem both = reduceOntoTheta(model, s.theta, noise, loss, two, q, 0.0, true, 2,
                                               &ws, FrameOptions(), nullptr, &got);
    ASSERT_EQ(got.rows(), nf);
    EXPECT_GT(want.norm(), 1.0);
    EXPECT_LT((got - want).norm(), 1e-9 * want.norm());
    // Asking for it changes nothing else.
    const ReducedSystem plain = reduceOntoTheta(model, s.theta, noise, loss, two, q, 0.0, true, 2,
                                                &ws);
    EXPECT_LT((plain.g - both.g).norm(), 1e-12 * plain.g.norm());
    EXPECT_LT((plain.S - both.S).norm(), 1e-12 * plain.S.norm());
  }
}

}  // namespace
}  // namespace stac
