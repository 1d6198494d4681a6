// Cross-sensor prediction (evaluate.hpp): MAE against the injected noise with
// the true parameters, far worse with the paper's seed, exact on noise-free
// data with known offsets, missing readings, thread independence, and the
// parameter errors against a truth.
#include "stac/evaluate.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "stac/error.hpp"
#include "support/arm_fixture.hpp"

namespace stac {
namespace {

using test::ArmProblem;
using test::makeArmProblem;

constexpr int kMarker = 0, kJoint = 1, kTendon = 2;
constexpr double kSigmaMarker = 0.002, kSigmaScalar = 0.01;  // arm_fixture's σ
constexpr double kHalfNormal = 0.7979;   // E|N(0,1)|
constexpr double kChi3Mean = 1.5958;     // E‖N(0, I3)‖

EvaluationOptions useGroups(std::initializer_list<int> groups, int threads = 2) {
  EvaluationOptions o;
  for (int g : groups) o.use[g] = true;
  o.threads = threads;
  return o;
}

const SensorPredictionError& sensorError(const EvaluationResult& r, const std::string& name) {
  for (const SensorPredictionError& s : r.sensors)
    if (s.name == name) return s;
  throw std::runtime_error("no sensor " + name);
}

TEST(Evaluate, TrueParametersFromMarkersPredictScalarsAtTheirNoise) {
  const ArmProblem p = makeArmProblem(600, 3);
  const EvaluationResult r =
      evaluatePrediction(p.robot, p.sensors, p.truth, p.obs, useGroups({kMarker}));
  EXPECT_EQ(r.frames, 600);
  ASSERT_TRUE(r.group[kJoint].predicted && r.group[kTendon].predicted);
  EXPECT_FALSE(r.group[kJoint].used);
  EXPECT_TRUE(r.group[kMarker].used);
  EXPECT_EQ(r.group[kJoint].count, 4 * 600);
  // The base marker does not move with q: its error is pure noise,
  // E‖N(0, σ² I3)‖ = 1.596σ.
  EXPECT_NEAR(sensorError(r, "m_base").mae, kChi3Mean * kSigmaMarker, 0.1 * kSigmaMarker);
  // The markers that fitted q absorb part of their noise: below 1.6σ.
  EXPECT_LT(r.group[kMarker].mae, kChi3Mean * kSigmaMarker);
  EXPECT_GT(r.group[kMarker].mae, 0.6 * kSigmaMarker);
  // A held-out reading's error is its own noise (E|N| = 0.80σ) plus what the
  // q estimate adds; it cannot be much below the noise. j1, j2 and the
  // cylinder are well observed by the markers.
  for (const char* name : {"j1_pot", "j2_pot", "cyl"}) {
    EXPECT_GT(sensorError(r, name).mae, 0.72 * kSigmaScalar) << name;
    EXPECT_LT(sensorError(r, name).mae, 2.5 * kSigmaScalar) << name;
  }
  EXPECT_GT(r.group[kJoint].mae, 0.72 * kSigmaScalar);
  EXPECT_LT((r.q - p.q_true).leftCols(2).cwiseAbs().mean(), 0.02);
  EXPECT_LT((r.q - p.q_true).leftCols(2).cwiseAbs().maxCoeff(), 0.1);
  // j3 turns about the axis of l3, and the l4 markers sit within 6 cm of it:
  // the markers see j3 poorly, and its pot's prediction shows it.
  EXPECT_GT(sensorError(r, "j3_pot").mae, sensorError(r, "j2_pot").mae);
}

TEST(Evaluate, TrueParametersFromScalarsPredictMarkersAtTheirNoise) {
  const ArmProblem p = makeArmProblem(600, 4);
  const EvaluationResult r =
      evaluatePrediction(p.robot, p.sensors, p.truth, p.obs, useGroups({kJoint, kTendon}));
  EXPECT_TRUE(r.group[kJoint].used && r.group[kTendon].used && !r.group[kMarker].used);
  EXPECT_EQ(r.group[kMarker].count, 5 * 600);
  // Marker noise alone gives 1.6σ; q from pots adds the lever arm times the
  // angle error (a few mm on this 0.5 m arm).
  EXPECT_GT(r.group[kMarker].mae, 0.95 * kChi3Mean * kSigmaMarker);
  EXPECT_LT(r.group[kMarker].mae, 6.0 * kSigmaMarker);
  // Five readings fit four joint angles: the used groups absorb most noise.
  EXPECT_LT(r.group[kJoint].mae, 0.5 * kHalfNormal * kSigmaScalar);
  EXPECT_LT(r.group[kTendon].mae, kHalfNormal * kSigmaScalar);
}

TEST(Evaluate, SeedParametersAreFarWorseThanTheTruth) {
  const ArmProblem p = makeArmProblem(400, 5);
  for (int use : {kMarker, kJoint}) {
    SCOPED_TRACE(use);
    const EvaluationResult good =
        evaluatePrediction(p.robot, p.sensors, p.truth, p.obs, useGroups({use}));
    const EvaluationResult seed =
        evaluatePrediction(p.robot, p.sensors, p.seed, p.obs, useGroups({use}));
    for (int g : {kMarker, kJoint, kTendon}) {
      if (g == use) continue;
      EXPECT_GT(seed.group[g].mae, 10 * good.group[g].mae) << groupName(SensorGroup(g));
    }
  }
  const EvaluationResult seed =
      evaluatePrediction(p.robot, p.sensors, p.seed, p.obs, useGroups({kJoint}));
  // Seed mocap frame is the identity, the true one is metres away.
  EXPECT_GT(seed.group[kMarker].mae, 0.1);
}

TEST(Evaluate, NoiseFreeDataIsPredictedExactly) {
  const ArmProblem p = makeArmProblem(300, 6, /*noise_scale=*/0.0);
  for (auto use : {std::vector<int>{kMarker}, std::vector<int>{kJoint},
                   std::vector<int>{kMarker, kJoint, kTendon}}) {
    EvaluationOptions o;
    for (int g : use) o.use[g] = true;
    const EvaluationResult r = evaluatePrediction(p.robot, p.sensors, p.truth, p.obs, o);
    EXPECT_LT(r.group[kMarker].mae, 1e-7);
    EXPECT_LT(r.group[kJoint].mae, 1e-6);
    EXPECT_LT(r.group[kTendon].mae, 1e-6);
  }
}

TEST(Evaluate, KnownOffsetsGiveTheirSize) {
  // Noise-free data. A joint column off by 0.05, q from the markers: exactly
  // that sensor's error is 0.05.
  ArmProblem p = makeArmProblem(300, 7, 0.0);
  p.obs.joint.col(2).array() += 0.05;
  const EvaluationResult from_markers =
      evaluatePrediction(p.robot, p.sensors, p.truth, p.obs, useGroups({kMarker}));
  EXPECT_NEAR(sensorError(from_markers, "j3_pot").mae, 0.05, 1e-6);
  EXPECT_LT(sensorError(from_markers, "j1_pot").mae, 1e-6);
  EXPECT_NEAR(from_markers.group[kJoint].mae, 0.05 / 4, 1e-6);
  // A marker off by (0.03, 0.04, 0), q from the pots: its error is the
  // Euclidean distance 0.05 m.
  ArmProblem clean = makeArmProblem(300, 7, 0.0);
  clean.obs.marker.col(3).array() += 0.03;
  clean.obs.marker.col(4).array() += 0.04;
  const EvaluationResult r =
      evaluatePrediction(clean.robot, clean.sensors, clean.truth, clean.obs, useGroups({kJoint}));
  EXPECT_NEAR(sensorError(r, "m_l2a").mae, 0.05, 1e-7);
  EXPECT_LT(sensorError(r, "m_l2b").mae, 1e-7);
  EXPECT_NEAR(r.group[kMarker].mae, 0.05 / 5, 1e-7);
}

TEST(Evaluate, MissingReadingsAreSkippedAndCounted) {
  ArmProblem p = makeArmProblem(300, 8, 1.0, /*dropout=*/0.3);
  p.obs.joint(10, 0) = std::numeric_limits<double>::quiet_NaN();
  // A marker that is never seen: its MAE is undefined, not zero.
  p.obs.marker.col(6).setConstant(std::numeric_limits<double>::quiet_NaN());
  p.obs.marker.col(7).setConstant(std::numeric_limits<double>::quiet_NaN());
  p.obs.marker.col(8).setConstant(std::numeric_limits<double>::quiet_NaN());
  const EvaluationResult r =
      evaluatePrediction(p.robot, p.sensors, p.truth, p.obs, useGroups({kJoint}));
  int present = 0;
  for (int t = 0; t < 300; ++t)
    for (int m = 0; m < 5; ++m) present += std::isfinite(p.obs.marker(t, 3 * m)) ? 1 : 0;
  EXPECT_EQ(r.group[kMarker].count, present);
  EXPECT_EQ(sensorError(r, "j1_pot").count, 299);
  EXPECT_EQ(sensorError(r, "m_l2b").count, 0);
  EXPECT_TRUE(std::isnan(sensorError(r, "m_l2b").mae));
  EXPECT_TRUE(std::isfinite(r.group[kMarker].mae));
  const std::string json = evaluationJson(r);
  EXPECT_NE(json.find("\"m_l2b\": {\"mae\": null, \"count\": 0}"), std::string::npos) << json;
  EXPECT_EQ(json.find("nan"), std::string::npos) << json;
}

TEST(Evaluate, PredictSubsetAndThreadIndependence) {
  const ArmProblem p = makeArmProblem(200, 9);
  EvaluationOptions o = useGroups({kMarker}, 1);
  o.predict[kMarker] = false;
  o.predict[kTendon] = false;
  const EvaluationResult one = evaluatePrediction(p.robot, p.sensors, p.truth, p.obs, o);
  EXPECT_FALSE(one.group[kMarker].predicted);
  EXPECT_TRUE(one.group[kJoint].predicted);
  ASSERT_EQ(one.sensors.size(), 4u);
  o.threads = 3;
  const EvaluationResult three = evaluatePrediction(p.robot, p.sensors, p.truth, p.obs, o);
  EXPECT_EQ(one.q, three.q);
  EXPECT_EQ(one.group[kJoint].mae, three.group[kJoint].mae);
  const std::string json = evaluationJson(one);
  EXPECT_NE(json.find("\"mae\": {\"joint\": "), std::string::npos) << json;
  EXPECT_NE(json.find("\"use\": [\"marker\"]"), std::string::npos) << json;
}

TEST(Evaluate, InvalidOptionsAndMismatchedInputsThrow) {
  const ArmProblem p = makeArmProblem(20, 10);
  EvaluationOptions none;
  std::string error;
  EXPECT_FALSE(none.isValid(&error));
  EXPECT_NE(error.find("no sensor group"), std::string::npos);
  EXPECT_THROW(evaluatePrediction(p.robot, p.sensors, p.truth, p.obs, none),
               std::invalid_argument);
  SensorSet no_tendons = p.sensors;
  no_tendons.tendon_sensors.clear();
  SensorParameters theta = p.truth;
  theta.tendon_sensor.clear();
  Observations obs = p.obs;
  obs.tendon.resize(obs.num_frames, 0);
  EXPECT_THROW(evaluatePrediction(p.robot, no_tendons, theta, obs, useGroups({kTendon})),
               std::invalid_argument);
  EXPECT_THROW(evaluatePrediction(p.robot, no_tendons, theta, p.obs, useGroups({kJoint})),
               std::invalid_argument);
  // A group without sensors is not predicted and absent from the JSON.
  const EvaluationResult r = evaluatePrediction(p.robot, no_tendons, theta, obs, useGroups({kJoint}));
  EXPECT_FALSE(r.group[kTendon].present);
  EXPECT_EQ(evaluationJson(r).find("tendon"), std::string::npos);
}

TEST(Evaluate, TruthErrorsAreZeroForTheTruthAndMeasureEachChange) {
  const ArmProblem p = makeArmProblem(10, 11);
  const auto same = compareToTruth(p.sensors, p.truth, p.sensors, p.truth, "truth.yaml");
  // mocap (2) + 5 markers + 4 joint sensors x 2 + 1 tendon x 2.
  ASSERT_EQ(same.size(), 2u + 5u + 8u + 2u);
  for (const ParameterError& e : same) EXPECT_NEAR(e.error, 0.0, 1e-12) << e.name;

  SensorParameters est = p.truth;
  est.joint_sensor[1].gain += 0.25;
  est.tendon_sensor[0].bias -= 0.5;
  est.marker_position[2] += Eigen::Vector3d(0.0, 0.003, 0.004);
  est.mocap.translation += Eigen::Vector3d(0.1, 0.0, 0.0);
  est.mocap.rotation = Eigen::Quaterniond(Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitY())) *
                       p.truth.mocap.rotation;
  // The truth's sensors listed in another order still match by name.
  SensorSet truth_sensors = p.sensors;
  SensorParameters truth = p.truth;
  std::swap(truth_sensors.joint_sensors[0], truth_sensors.joint_sensors[3]);
  std::swap(truth.joint_sensor[0], truth.joint_sensor[3]);
  const auto errs = compareToTruth(p.sensors, est, truth_sensors, truth, "truth.yaml");
  for (const ParameterError& e : errs) {
    double expected = 0.0;
    if (e.name == "j2_pot.gain") expected = 0.25;
    if (e.name == "cyl.bias") expected = -0.5;
    if (e.name == "m_l2b.position") expected = 0.005;
    if (e.name == "mocap.translation") expected = 0.1;
    if (e.name == "mocap.rotation") expected = 0.2;
    EXPECT_NEAR(e.error, expected, 1e-12) << e.name;
  }
  const std::string json = evaluationJson(EvaluationResult{}, &errs);
  EXPECT_NE(json.find("\"j2_pot.gain\": 0.25"), std::string::npos) << json;
  EXPECT_NE(evaluationReport(EvaluationResult{}, &errs).find("mocap.rotation"), std::string::npos);

  // A sensor missing from the truth, or on another joint, is bad input.
  SensorSet fewer = p.sensors;
  SensorParameters fewer_theta = p.truth;
  fewer.joint_sensors.pop_back();
  fewer_theta.joint_sensor.pop_back();
  try {
    compareToTruth(p.sensors, p.truth, fewer, fewer_theta, "truth.yaml");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("j4_pot"), std::string::npos) << e.what();
    EXPECT_EQ(e.file(), "truth.yaml");
  }
  EXPECT_THROW(compareToTruth(fewer, fewer_theta, p.sensors, p.truth, "t"), InputError);
  SensorSet moved = p.sensors;
  moved.joint_sensors[0].joint = p.sensors.joint_sensors[1].joint;
  moved.joint_sensors[0].joint_name = p.sensors.joint_sensors[1].joint_name;
  EXPECT_THROW(compareToTruth(p.sensors, p.truth, moved, p.truth, "t"), InputError);
}

TEST(Evaluate, ReportMarksUsedGroupsInParentheses) {
  const ArmProblem p = makeArmProblem(100, 12);
  const EvaluationResult r =
      evaluatePrediction(p.robot, p.sensors, p.truth, p.obs, useGroups({kJoint, kTendon}));
  const std::string text = evaluationReport(r);
  EXPECT_NE(text.find("estimated from joint,tendon"), std::string::npos) << text;
  EXPECT_NE(text.find("(" ), std::string::npos);
  // The marker MAE is printed bare, the joint one in parentheses.
  char buf[64];
  std::snprintf(buf, sizeof buf, "(%.6g)", r.group[kJoint].mae);
  EXPECT_NE(text.find(buf), std::string::npos) << text;
  std::snprintf(buf, sizeof buf, "(%.6g)", r.group[kMarker].mae);
  EXPECT_EQ(text.find(buf), std::string::npos) << text;
}

}  // namespace
}  // namespace stac
