// The paper's baselines against known truth: the EKF (§IV-A) and the
// classical regression with σ_p -> 0 (§IV-B). Both are started near the
// truth (the regime the paper gives them: a manual calibration, q_0 = truth
// for the EKF) on smooth, lightly noisy motion, and must land within stated
// tolerances of the truth. Also: the dense frame Jacobians they are built on
// and the classical chain rule through q = a p + c against central
// differences, and the refusal of robots the classical method cannot handle.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <random>

#include "stac/calibrate.hpp"
#include "stac/theta_space.hpp"
#include "methods/classical.hpp"
#include "stac/error.hpp"
#include "model/frame_jacobian.hpp"
#include "stac/sensors_file.hpp"
#include "stac/simulate.hpp"
#include "support/arm_files.hpp"
#include "support/arm_fixture.hpp"
#include "support/test_util.hpp"

namespace stac {
namespace {

// Largest errors of an estimate against the truth, per kind of parameter,
// in comparable units: gains relative, biases in the sensed quantity's unit
// (rad or m: bias / |gain|), positions in metres, rotation in radians.
struct ParamError {
  double rotation = 0, translation = 0, marker = 0;
  double joint_gain = 0, joint_bias = 0, tendon_gain = 0, tendon_bias = 0;
};

ParamError paramError(const SensorSet& s, const SensorParameters& est,
                      const SensorParameters& truth) {
  const ThetaSpace space(s);
  const Eigen::VectorXd d = space.minus(est, truth);
  ParamError e;
  e.rotation = d.segment<3>(ThetaSpace::kRotationOffset).norm();
  e.translation = d.segment<3>(ThetaSpace::kTranslationOffset).norm();
  for (size_t m = 0; m < s.markers.size(); ++m)
    e.marker = std::max(e.marker, d.segment<3>(space.markerOffset(static_cast<int>(m))).norm());
  for (size_t j = 0; j < s.joint_sensors.size(); ++j) {
    const int o = space.jointOffset(static_cast<int>(j));
    const double g = std::abs(truth.joint_sensor[j].gain);
    e.joint_gain = std::max(e.joint_gain, std::abs(d[o]) / g);
    e.joint_bias = std::max(e.joint_bias, std::abs(d[o + 1]) / g);
  }
  for (size_t j = 0; j < s.tendon_sensors.size(); ++j) {
    const int o = space.tendonOffset(static_cast<int>(j));
    const double g = std::abs(truth.tendon_sensor[j].gain);
    e.tendon_gain = std::max(e.tendon_gain, std::abs(d[o]) / g);
    e.tendon_bias = std::max(e.tendon_bias, std::abs(d[o + 1]) / g);
  }
  return e;
}

std::ostream& operator<<(std::ostream& o, const ParamError& e) {
  return o << "rotation " << e.rotation << " translation " << e.translation << " marker "
           << e.marker << " joint gain " << e.joint_gain << " bias " << e.joint_bias
           << " tendon gain " << e.tendon_gain << " bias " << e.tendon_bias;
}

void debugPrint(const ParamError& e) {
  if (std::getenv("STAC_DEBUG")) std::cerr << e << "\n";
}

// A "manual calibration": the truth off by `k` times (3°, 2 cm frame, 1 cm
// markers, 10% gains, 0.05 rad or 5 mm biases). Fixed entries stay.
SensorParameters nearSeed(const SensorSet& s, const SensorParameters& truth, unsigned seed,
                          double k = 1.0) {
  std::mt19937 rng(seed);
  auto uni = [&](double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); };
  auto dir = [&]() { return Eigen::Vector3d(uni(-1, 1), uni(-1, 1), uni(-1, 1)).normalized(); };
  SensorParameters p = truth;
  if (!s.mocap_frame_fixed.any()) {
    p.mocap.rotation =
        Eigen::Quaterniond(Eigen::AngleAxisd(0.05 * k, dir())) * truth.mocap.rotation;
    p.mocap.translation += 0.02 * k * dir();
  }
  for (size_t m = 0; m < s.markers.size(); ++m)
    if (!s.markers[m].fixed) p.marker_position[m] += 0.01 * k * dir();
  for (size_t j = 0; j < s.joint_sensors.size(); ++j) {
    if (s.joint_sensors[j].fixed.any()) continue;
    const double g = truth.joint_sensor[j].gain;
    p.joint_sensor[j].gain = g * (1 + 0.1 * k * (uni(0, 1) < 0.5 ? -1 : 1));
    p.joint_sensor[j].bias += 0.05 * k * std::abs(g) * (uni(0, 1) < 0.5 ? -1 : 1);
  }
  for (size_t j = 0; j < s.tendon_sensors.size(); ++j) {
    if (s.tendon_sensors[j].fixed.any()) continue;
    const double g = truth.tendon_sensor[j].gain;
    p.tendon_sensor[j].gain = g * (1 + 0.1 * k * (uni(0, 1) < 0.5 ? -1 : 1));
    p.tendon_sensor[j].bias += 0.005 * k * std::abs(g) * (uni(0, 1) < 0.5 ? -1 : 1);
  }
  return p;
}

CalibrationOptions options(Method m) {
  CalibrationOptions o;
  o.method = m;
  o.threads = 2;
  return o;
}

// A bundled robot: sensors (and fixed flags) from its seed file, values
// from its truth file, readings simulated at noise_scale.
struct Bundled {
  RobotModel robot;
  SensorSet sensors;
  SensorParameters truth;
  RowMatrix q_true;
  Observations obs;
};
Bundled bundled(const std::string& name, int frames, double noise_scale) {
  RobotModel robot = RobotModel::fromFile(test::dataPath(name + ".urdf"));
  const SensorsFile seed = loadSensorsFile(test::dataPath(name + "_seed.yaml"), robot);
  const SensorsFile truth = loadSensorsFile(test::dataPath(name + "_truth.yaml"), robot);
  const MeasurementModel model(robot, seed.sensors);
  SimulationOptions so;
  so.frames = frames;
  so.seed = 3;
  so.noise_scale = noise_scale;
  Simulation sim = simulate(model, truth.theta, so);
  Observations obs = bindLog(sim.data.log, seed.sensors, "seed", 1.0);
  return {std::move(robot), seed.sensors, truth.theta, std::move(sim.q), std::move(obs)};
}

}  // namespace

// ---- Derivatives ----

// dr/dθ (left perturbation for the rotation) and dr/dq of denseFrame()
// against central differences of evaluateFrame()'s residuals.
TEST(FrameJacobian, DenseAssemblyMatchesCentralDifferences) {
  test::ArmProblem p = test::makeArmProblem(5, 7);
  const MeasurementModel model(p.robot, p.sensors);
  const NoiseModel noise = NoiseModel::fromSeeds(p.sensors);
  for (LossKind kind : {LossKind::kNone, LossKind::kHuber}) {
    const RobustLoss loss(kind, 1.0);
    FrameWorkspace ws(model);
    const FrameReadings fr = frameReadings(p.obs, 2);
    const Eigen::VectorXd q = p.q_true.row(2).transpose() + Eigen::VectorXd::Constant(4, 0.03);
    const SensorParameters theta = nearSeed(p.sensors, p.truth, 1);
    FrameOptions eo;
    eo.theta_jacobians = true;
    evaluateFrame(model, theta, noise, loss, fr, q, eo, &ws);
    DenseFrame df;
    denseFrame(model, ws, nullptr, &df);
    ASSERT_EQ(df.rows, 5 * 3 + 4 + 1);
    auto residual = [&](const SensorParameters& th, const Eigen::VectorXd& qq) {
      FrameWorkspace w(model);
      evaluateFrame(model, th, noise, loss, fr, qq, eo, &w);
      DenseFrame d;
      denseFrame(model, w, nullptr, &d);
      return d.r;
    };
    const double h = 1e-6;
    for (int i = 0; i < model.thetaSpace().size(); ++i) {
      SensorParameters plus = theta, minus = theta;
      auto nudge = [&](SensorParameters* t, double e) {
        Eigen::VectorXd d = Eigen::VectorXd::Zero(model.thetaSpace().size());
        d[i] = e;
        const Eigen::Vector3d rot = d.head<3>();
        if (rot.norm() > 0)
          t->mocap.rotation = Eigen::Quaterniond(Eigen::AngleAxisd(rot.norm(), rot.normalized())) *
                              t->mocap.rotation;
        t->mocap.translation += d.segment<3>(3);
        for (size_t m = 0; m < t->marker_position.size(); ++m)
          t->marker_position[m] += d.segment<3>(model.thetaSpace().markerOffset(static_cast<int>(m)));
        for (size_t j = 0; j < t->joint_sensor.size(); ++j) {
          t->joint_sensor[j].gain += d[model.thetaSpace().jointOffset(static_cast<int>(j))];
          t->joint_sensor[j].bias += d[model.thetaSpace().jointOffset(static_cast<int>(j)) + 1];
        }
        for (size_t j = 0; j < t->tendon_sensor.size(); ++j) {
          t->tendon_sensor[j].gain += d[model.thetaSpace().tendonOffset(static_cast<int>(j))];
          t->tendon_sensor[j].bias += d[model.thetaSpace().tendonOffset(static_cast<int>(j)) + 1];
        }
      };
      nudge(&plus, h);
      nudge(&minus, -h);
      const Eigen::VectorXd fd = (residual(plus, q) - residual(minus, q)) / (2 * h);
      EXPECT_LT((fd - df.Jtheta.col(i)).norm(), 1e-5 * std::max(1.0, fd.norm()))
          << model.thetaSpace().names()[i];
    }
    for (int j = 0; j < model.dof(); ++j) {
      Eigen::VectorXd qp = q, qm = q;
      qp[j] += h;
      qm[j] -= h;
      const Eigen::VectorXd fd = (residual(theta, qp) - residual(theta, qm)) / (2 * h);
      EXPECT_LT((fd - df.Jq.col(j)).norm(), 1e-5 * std::max(1.0, fd.norm())) << "q" << j;
    }
  }
}

// The classical frame's Jacobian w.r.t. its parameters (θ, with (a, c) in
// the slots of the defining joint sensors) against central differences. A
// second pot on j2 is an ordinary (non-defining) reading.
TEST(Classical, FrameJacobianMatchesCentralDifferences) {
  test::ArmProblem p = test::makeArmProblem(5, 9);
  JointSensorConfig extra = p.sensors.joint_sensors[1];
  extra.name = "j2_pot_b";
  p.sensors.joint_sensors.push_back(extra);
  p.truth.joint_sensor.push_back({0.7, -0.2});
  {
    const MeasurementModel m0(p.robot, p.sensors);
    std::mt19937 rng(3);
    test::simulateReadings(m0, p.truth, p.q_true, 1.0, 0.0, rng, &p.obs);
  }
  const MeasurementModel model(p.robot, p.sensors);
  const NoiseModel noise = NoiseModel::fromSeeds(p.sensors);
  const JointSources sources = findJointSources(p.robot, p.sensors);
  ASSERT_TRUE(sources.uncovered.empty());
  ASSERT_EQ(sources.defining, (std::vector<bool>{true, true, true, true, false}));
  ClassicalParameters params;
  params.theta = nearSeed(p.sensors, p.truth, 4);
  for (const GainBias& gb : params.theta.joint_sensor) params.inverse.push_back(inverseMap(gb));
  FrameWorkspace ws(model);
  const FrameReadings fr = frameReadings(p.obs, 3);
  const RobustLoss loss;
  Eigen::VectorXd r;
  Eigen::MatrixXd J;
  ASSERT_TRUE(classicalFrame(model, sources, params, noise, loss, fr, &ws, &r, &J));
  EXPECT_EQ(r.size(), 5 * 3 + 1 + 1);  // markers, the second pot, the cylinder
  auto residual = [&](const ClassicalParameters& cp) {
    FrameWorkspace w(model);
    Eigen::VectorXd rr;
    classicalFrame(model, sources, cp, noise, loss, fr, &w, &rr, nullptr);
    return rr;
  };
  const double h = 1e-6;
  for (int i = 0; i < model.thetaSpace().size(); ++i) {
    auto nudged = [&](double e) {
      ClassicalParameters c = params;
      if (i < 3) {
        const Eigen::Vector3d d = Eigen::Vector3d::Unit(i) * e;
        const Eigen::Quaterniond dq(Eigen::AngleAxisd(d.norm(), d.normalized()));
        c.theta.mocap.rotation = dq * c.theta.mocap.rotation;
      } else if (i < 6) {
        c.theta.mocap.translation[i - 3] += e;
      } else if (i < model.thetaSpace().jointOffset(0)) {
        c.theta.marker_position[(i - 6) / 3][(i - 6) % 3] += e;
      } else if (i < model.thetaSpace().tendonOffset(0)) {
        const int s = (i - model.thetaSpace().jointOffset(0)) / 2, k = (i - model.thetaSpace().jointOffset(0)) % 2;
        if (sources.defining[s]) (k == 0 ? c.inverse[s].a : c.inverse[s].c) += e;
        else (k == 0 ? c.theta.joint_sensor[s].gain : c.theta.joint_sensor[s].bias) += e;
      } else {
        const int s = (i - model.thetaSpace().tendonOffset(0)) / 2, k = (i - model.thetaSpace().tendonOffset(0)) % 2;
        (k == 0 ? c.theta.tendon_sensor[s].gain : c.theta.tendon_sensor[s].bias) += e;
      }
      return c;
    };
    const Eigen::VectorXd fd = (residual(nudged(h)) - residual(nudged(-h))) / (2 * h);
    EXPECT_LT((fd - J.col(i)).norm(), 1e-5 * std::max(1.0, fd.norm())) << model.thetaSpace().names()[i];
  }
  // (a, c) is the inverse of (gain, bias).
  const GainBias gb{-1.7, 0.4};
  EXPECT_NEAR(forwardMap(inverseMap(gb)).gain, gb.gain, 1e-15);
  EXPECT_NEAR(forwardMap(inverseMap(gb)).bias, gb.bias, 1e-15);
}

TEST(Classical, FindsTheSensorOfEveryJointAndNamesTheRest) {
  test::ArmProblem p = test::makeArmProblem(2, 1);
  p.sensors.joint_sensors.erase(p.sensors.joint_sensors.begin() + 2);  // j3_pot
  const JointSources s = findJointSources(p.robot, p.sensors);
  EXPECT_EQ(s.sensor, (std::vector<int>{0, 1, -1, 2}));
  EXPECT_EQ(s.uncovered, (std::vector<std::string>{"j3"}));
}

// ---- Recovery of the truth ----

// The paper's EKF (one update per frame) and the iterated EKF, which
// relinearises and so tracks the fast motion of this fixture (up to ~0.1
// rad per frame) more closely.
TEST(Ekf, ArmFromANearSeedAndTheTrueFirstPose) {
  test::ArmProblem p = test::makeArmProblem(400, 11, 0.1);
  const SensorParameters seed = nearSeed(p.sensors, p.truth, 2);
  for (int iterations : {1, 3}) {
    SCOPED_TRACE(::testing::Message() << iterations << " update(s) per frame");
    const double k = iterations == 1 ? 1.0 : 0.25;  // tolerance scale
    CalibrationOptions o = options(Method::kEkf);
    o.ekf.initial_q = p.q_true.row(0).transpose();
    o.ekf.iterations = iterations;
    int reports = 0;
    o.progress = [&](const IterationReport& r) {
      ++reports;
      EXPECT_EQ(r.stage, "ekf");
    };
    RowMatrix q;
    const CalibrationResult r = calibrate(p.robot, p.sensors, seed, p.obs, o, &q);
    EXPECT_LE(reports, 10);
    EXPECT_GE(reports, 9);
    const ParamError e = paramError(p.sensors, r.theta, p.truth);
    debugPrint(e);
    SCOPED_TRACE(::testing::Message() << e);
    EXPECT_LT(e.rotation, 0.01 * k);
    EXPECT_LT(e.translation, 0.005 * k);
    EXPECT_LT(e.marker, 0.003 * k);
    EXPECT_LT(e.joint_gain, 0.01 * k);
    EXPECT_LT(e.joint_bias, 0.01 * k);
    EXPECT_LT(e.tendon_gain, 0.01 * k);
    EXPECT_LT(e.tendon_bias, 0.001 * k);
    // Tracking: the filtered q of the second half.
    const double q_err = (q.bottomRows(200) - p.q_true.bottomRows(200)).cwiseAbs().maxCoeff();
    if (std::getenv("STAC_DEBUG")) std::cerr << "q error " << q_err << "\n";
    EXPECT_LT(q_err, 0.02 * k);
    // Fixed markers stay; the reported std shrank from the seed's.
    EXPECT_EQ(r.theta.marker_position[0], p.truth.marker_position[0]);
    EXPECT_EQ(r.std.marker_position[0], Eigen::Vector3d::Zero());
    EXPECT_GT(r.std.joint_sensor[0].gain, 0.0);
    EXPECT_LT(r.std.joint_sensor[0].gain, 0.3 * 0.1);
    EXPECT_EQ(r.summary.method, "ekf");
    EXPECT_EQ(r.summary.frames, 400);
    EXPECT_TRUE(r.summary.unidentifiable.empty());
    EXPECT_LT(r.summary.after_rms[0], 0.002);
  }
}

TEST(Ekf, FixedSensorIsNotInTheState) {
  test::ArmProblem p = test::makeArmProblem(200, 13, 0.1);
  p.sensors.joint_sensors[1].fixed = FixedGainBias::both(true);
  SensorParameters seed = nearSeed(p.sensors, p.truth, 5);
  CalibrationOptions o = options(Method::kEkf);
  o.ekf.initial_q = p.q_true.row(0).transpose();
  const CalibrationResult r = calibrate(p.robot, p.sensors, seed, p.obs, o);
  EXPECT_EQ(r.theta.joint_sensor[1].gain, p.truth.joint_sensor[1].gain);
  EXPECT_EQ(r.theta.joint_sensor[1].bias, p.truth.joint_sensor[1].bias);
  EXPECT_EQ(r.std.joint_sensor[1].gain, 0.0);
  EXPECT_NE(r.theta.joint_sensor[0].gain, seed.joint_sensor[0].gain);
}

// Two tendons across a gimbal, markers: the case classical methods cannot
// handle. q_0 solved from frame 0 with the seed (no truth given).
TEST(Ekf, Gimbal2FromANearSeed) {
  const Bundled b = bundled("gimbal2", 400, 0.1);
  const SensorParameters seed = nearSeed(b.sensors, b.truth, 3);
  RowMatrix q;
  const CalibrationResult r =
      calibrate(b.robot, b.sensors, seed, b.obs, options(Method::kEkf), &q);
  const ParamError e = paramError(b.sensors, r.theta, b.truth);
  debugPrint(e);
  SCOPED_TRACE(::testing::Message() << e);
  EXPECT_LT(e.rotation, 0.01);
  EXPECT_LT(e.translation, 0.005);
  EXPECT_LT(e.marker, 0.003);
  EXPECT_LT(e.tendon_gain, 0.01);
  EXPECT_LT(e.tendon_bias, 0.001);
  const double q_err = (q.bottomRows(200) - b.q_true.bottomRows(200)).cwiseAbs().maxCoeff();
  if (std::getenv("STAC_DEBUG")) std::cerr << "q error " << q_err << "\n";
  EXPECT_LT(q_err, 0.02);
}

TEST(Classical, ArmFromANearSeed) {
  test::ArmProblem p = test::makeArmProblem(400, 11, 0.1);
  const SensorParameters seed = nearSeed(p.sensors, p.truth, 2);
  int reports = 0;
  CalibrationOptions o = options(Method::kClassical);
  o.progress = [&](const IterationReport& r) {
    ++reports;
    EXPECT_EQ(r.stage, "classical");
  };
  RowMatrix q;
  const CalibrationResult r = calibrate(p.robot, p.sensors, seed, p.obs, o, &q);
  EXPECT_TRUE(r.summary.converged);
  EXPECT_EQ(reports, r.summary.iterations);
  const ParamError e = paramError(p.sensors, r.theta, p.truth);
  debugPrint(e);
  SCOPED_TRACE(::testing::Message() << e);
  // The pots' noise (σ 0.001 rad-equivalent here) goes straight into q: the
  // errors are larger than a method that estimates q would make.
  EXPECT_LT(e.rotation, 0.005);
  EXPECT_LT(e.translation, 0.003);
  EXPECT_LT(e.marker, 0.003);
  EXPECT_LT(e.joint_gain, 0.01);
  EXPECT_LT(e.joint_bias, 0.005);
  EXPECT_LT(e.tendon_gain, 0.01);
  EXPECT_LT(e.tendon_bias, 0.001);
  // q is the pots' reading mapped by the fitted inverse.
  EXPECT_NEAR(q(7, 1), (p.obs.joint(7, 1) - r.theta.joint_sensor[1].bias) /
                           r.theta.joint_sensor[1].gain, 1e-12);
  EXPECT_EQ(r.summary.method, "classical");
  EXPECT_TRUE(r.summary.unidentifiable.empty());
  // Reported std are the right size: the errors within 5 std.
  for (size_t j = 0; j < p.sensors.joint_sensors.size(); ++j)
    EXPECT_LT(std::abs(r.theta.joint_sensor[j].gain - p.truth.joint_sensor[j].gain),
              5 * r.std.joint_sensor[j].gain) << j;
}

TEST(Classical, SkipsFramesWithAMissingPotReading) {
  test::ArmProblem p = test::makeArmProblem(300, 12, 0.1);
  for (int t = 10; t < 300; t += 10) p.obs.joint(t, t % 4) = NAN;
  const SensorParameters seed = nearSeed(p.sensors, p.truth, 6);
  RowMatrix q;
  const CalibrationResult r =
      calibrate(p.robot, p.sensors, seed, p.obs, options(Method::kClassical), &q);
  EXPECT_EQ(r.summary.frames, 300 - 29);
  EXPECT_TRUE(std::isnan(q(20, 0)));
  EXPECT_FALSE(std::isnan(q(20, 1)));
  const ParamError e = paramError(p.sensors, r.theta, p.truth);
  EXPECT_LT(e.joint_gain, 0.01) << e;
  EXPECT_LT(e.marker, 0.003) << e;
}

TEST(Classical, Hand24FromANearSeed) {
  const Bundled b = bundled("hand24", 300, 0.1);
  const SensorParameters seed = nearSeed(b.sensors, b.truth, 8);
  const CalibrationResult r =
      calibrate(b.robot, b.sensors, seed, b.obs, options(Method::kClassical));
  EXPECT_TRUE(r.summary.converged);
  const ParamError e = paramError(b.sensors, r.theta, b.truth);
  debugPrint(e);
  SCOPED_TRACE(::testing::Message() << e);
  EXPECT_LT(e.rotation, 0.005);
  EXPECT_LT(e.translation, 0.003);
  EXPECT_LT(e.marker, 0.003);
  EXPECT_LT(e.joint_gain, 0.02);
  EXPECT_LT(e.joint_bias, 0.01);
  EXPECT_LT(e.tendon_gain, 0.02);
  EXPECT_LT(e.tendon_bias, 0.001);
}

TEST(Classical, RefusesARobotWithJointsWithoutAJointSensor) {
  const Bundled b = bundled("gimbal2", 20, 0.1);
  try {
    calibrate(b.robot, b.sensors, b.truth, b.obs, options(Method::kClassical));
    FAIL() << "gimbal2 has no joint sensors";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("neck_pan, neck_tilt"), std::string::npos) << e.what();
  }
}

// ---- --ekf-initial-q ----

TEST(Ekf, FirstJointAnglesChecksTheColumns) {
  const RobotModel robot = RobotModel::fromString(test::kArmUrdf, "arm4");
  const Eigen::VectorXd q = firstJointAngles(
      parseLog("time,j2,j1,j3,j4\n0,0.2,0.1,0.3,0.4\n0.01,9,9,9,9\n", "q.csv"), robot);
  EXPECT_EQ(q, Eigen::Vector4d(0.1, 0.2, 0.3, 0.4));
  auto error = [&](const std::string& text) {
    try {
      firstJointAngles(parseLog(text, "q.csv"), robot);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(error("# q\ntime,j1,j2,j3,elbow\n0,0,0,0,0\n")
                .find("q.csv:2: joint-angle column 'elbow'"),
            std::string::npos);
  EXPECT_NE(error("j1,j2,j3\n0,0,0\n").find("q.csv:1: joint-angle columns missing for: j4"),
            std::string::npos);
  EXPECT_NE(error("j1,j2,j3,j4\n").find("q.csv:1: no joint angles"), std::string::npos);
  EXPECT_NE(error("j1,j2,j3,j4\n0,,0,0\n").find("q.csv:2: missing joint angle for j2"),
            std::string::npos);
}

}  // namespace stac
